//! The HTML page: vendored three.js as `data:` modules in an import map (a page opened
//! from `file://` may import `data:` URLs, and nothing is fetched), the viewer script,
//! its style, and the scene as a JSON script element.

use super::scene::SceneData;

/// The vendored three.js release (see `vendor/three/README.md`).
pub const THREE_VERSION: &str = "0.183.2";

const THREE_CORE: &str = include_str!("../../vendor/three/three.core.min.js");
const THREE_MODULE: &str = include_str!("../../vendor/three/three.module.min.js");
const ORBIT_CONTROLS: &str = include_str!("../../vendor/three/OrbitControls.js");
const VIEWER_JS: &str = include_str!("viewer.js");
const VIEWER_CSS: &str = include_str!("viewer.css");
const VIEWER_HTML: &str = include_str!("viewer.html");

/// `three.module.min.js` imports its core by a relative path, which a `data:` URL cannot
/// resolve; the page maps this bare name instead.
const CORE_IMPORT: &str = "from\"./three.core.min.js\"";
const CORE_NAME: &str = "three/core";

fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * i)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

fn data_url(js: &str) -> String {
    format!("data:text/javascript;base64,{}", base64(js.as_bytes()))
}

fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The whole page for a scene.
pub fn html(scene: &SceneData) -> String {
    let module = THREE_MODULE.replace(CORE_IMPORT, &format!("from\"{CORE_NAME}\""));
    let imports = serde_json::json!({
        "imports": {
            "three": data_url(&module),
            CORE_NAME: data_url(THREE_CORE),
            "three/addons/controls/OrbitControls.js": data_url(ORBIT_CONTROLS),
        }
    });
    // `</` may not appear inside a script element; in JSON it can only be in a string,
    // where `<\/` means the same.
    let data = serde_json::to_string(scene).unwrap_or_else(|_| "null".into()).replace("</", "<\\/");
    // User text goes in last, so no marker can come from it; braces are escaped anyway.
    let title = escape_html(&scene.scenario).replace('{', "&#123;");
    VIEWER_HTML
        .replace("{{CSS}}", VIEWER_CSS)
        .replace("{{IMPORTMAP}}", &imports.to_string())
        .replace("{{THREE_VERSION}}", THREE_VERSION)
        .replace("{{VIEWER}}", VIEWER_JS)
        .replace("{{TITLE}}", &title)
        .replace("{{SCENE}}", &data)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_the_rfc_examples() {
        // RFC 4648, section 10.
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
    }

    #[test]
    fn the_vendored_module_still_imports_its_core_by_that_path() {
        // If three.js changes how it imports its core, the import map would miss it.
        assert_eq!(THREE_MODULE.matches(CORE_IMPORT).count(), 2);
        assert!(!ORBIT_CONTROLS.contains("from './"), "OrbitControls imports only `three`");
        assert!(!VIEWER_JS.contains("</script"));
    }
}
