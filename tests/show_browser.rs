//! `declutter show` in a real browser: headless Chromium opens the page from `file://`
//! with name resolution switched off, and we check what a person would see — the page
//! says it is ready, logs nothing, paints the canvas, the arm moves between the start
//! and the middle, and the target rides in the hand from its grasp to its release. Screenshots are kept
//! under `target/tmp/show_browser/` as artefacts. Skips (saying why) when no Chromium
//! is installed; `.ci/run` installs it.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_declutter");
/// The page's background, as the viewer sets it (#f4f5f7).
const BACKGROUND: [u8; 3] = [0xf4, 0xf5, 0xf7];
const MAX_PAGE_BYTES: u64 = 5_000_000;

fn artefacts() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("show_browser");
    std::fs::create_dir_all(&dir).expect("artefact folder");
    dir
}

fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("DECLUTTER_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome", "google-chrome-stable"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |d| d.join(name)))
        .find(|p| p.is_file())
}

fn declutter(args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).current_dir(env!("CARGO_MANIFEST_DIR")).output().expect("run declutter")
}

/// Compiles an example and writes its page; returns the page's path.
fn page(example: &str) -> PathBuf {
    page_of(example, &format!("examples/{example}.dcl"))
}

/// Compiles a scenario and writes its page, named after `example`.
fn page_of(example: &str, dcl: &str) -> PathBuf {
    let dir = artefacts();
    let schedule = dir.join(format!("{example}.yaml"));
    let html = dir.join(format!("{example}.html"));
    let dcl = dcl.to_string();
    let out = declutter(&["compile", &dcl, "-o", schedule.to_str().unwrap()]);
    assert!(out.status.success(), "compile {example}: {}", String::from_utf8_lossy(&out.stderr));
    let out = declutter(&["show", &dcl, schedule.to_str().unwrap(), "-o", html.to_str().unwrap()]);
    assert!(out.status.success(), "show {example}: {}", String::from_utf8_lossy(&out.stderr));
    let size = std::fs::metadata(&html).expect("page written").len();
    assert!(size < MAX_PAGE_BYTES, "{example}: the page is {size} bytes");
    html
}

/// What one browser run gave: its stdout (the DOM when dumped) and stderr (the log).
struct Run {
    stdout: String,
    stderr: String,
}

fn browse(chrome: &Path, url: &str, extra: &[String]) -> Run {
    let profile = tempfile_dir();
    let mut cmd = Command::new(chrome);
    cmd.args([
        "--headless",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-background-networking",
        "--disable-component-update",
        "--no-first-run",
        "--disable-sync",
        // No name resolves: anything fetched over the network would fail.
        "--host-resolver-rules=MAP * ~NOTFOUND",
        "--window-size=1200,800",
        "--virtual-time-budget=8000",
        "--enable-logging=stderr",
        "--v=0",
    ])
    .arg(format!("--user-data-dir={}", profile.display()))
    .args(extra)
    .arg(url)
    .stdin(Stdio::null())
    .stdout(Stdio::piped())
    .stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("start chromium");
    let (mut out, mut err) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut out, &mut s);
        s
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut err, &mut s);
        s
    });
    let deadline = Instant::now() + Duration::from_secs(90);
    loop {
        if child.try_wait().expect("wait for chromium").is_some() {
            break;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("chromium did not finish within 90 s on {url}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let _ = std::fs::remove_dir_all(&profile);
    Run { stdout: reader.join().unwrap_or_default(), stderr: err_reader.join().unwrap_or_default() }
}

fn tempfile_dir() -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = artefacts().join(format!("profile-{}-{}", std::process::id(), N.fetch_add(1, Ordering::Relaxed)));
    std::fs::create_dir_all(&dir).expect("profile folder");
    dir
}

/// Console output, or a failure to load: the page logs nothing in normal use.
fn console_lines(stderr: &str) -> Vec<&str> {
    stderr.lines().filter(|l| l.contains(":CONSOLE") || l.contains("Uncaught")).collect()
}

/// The page's report (`#report`), read from the dumped DOM.
fn report(chrome: &Path, html: &Path, hash: &str) -> Value {
    let url = format!("file://{}#{hash}", html.display());
    let run = browse(chrome, &url, &["--dump-dom".to_string()]);
    assert!(
        console_lines(&run.stderr).is_empty(),
        "console output on {url}:\n{}",
        console_lines(&run.stderr).join("\n")
    );
    let start = run.stdout.find("<pre id=\"report\"").unwrap_or_else(|| panic!("no report in the DOM of {url}"));
    let body = &run.stdout[start..];
    let text = &body[body.find('>').unwrap() + 1..body.find("</pre>").unwrap()];
    let text = text.replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&");
    let v: Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("report of {url} is not JSON ({e}): {text}"));
    assert_eq!(v["ready"], true, "{url} did not get ready: {v}");
    assert_eq!(v["errors"], serde_json::json!([]), "{url} threw: {v}");
    v
}

/// RGB pixels of a screenshot, and its width.
fn screenshot(chrome: &Path, html: &Path, hash: &str, name: &str) -> (Vec<[u8; 3]>, usize) {
    let png = artefacts().join(name);
    let url = format!("file://{}#{hash}", html.display());
    let run = browse(chrome, &url, &[format!("--screenshot={}", png.display())]);
    assert!(
        console_lines(&run.stderr).is_empty(),
        "console output on {url}:\n{}",
        console_lines(&run.stderr).join("\n")
    );
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).expect("screenshot written")));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("PNG frame");
    let channels = info.color_type.samples();
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let pixels = buf[..info.buffer_size()].chunks(channels).map(|c| [c[0], c[1], c[2]]).collect();
    (pixels, info.width as usize)
}

/// Pixels of the 3-D view (left of the 300 px side panel, above the 40 px time bar).
fn view(pixels: &[[u8; 3]], width: usize) -> Vec<[u8; 3]> {
    let height = pixels.len() / width;
    (0..height - 40).flat_map(|y| (0..width - 300).map(move |x| (x, y))).map(|(x, y)| pixels[y * width + x]).collect()
}

fn differs(a: [u8; 3], b: [u8; 3]) -> bool {
    a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y) as u32).sum::<u32>() > 24
}

fn replay_checks(example: &str, dcl: &str) {
    let Some(chrome) = chromium() else {
        println!("skipped: no chromium on PATH (install Debian's `chromium`; .ci/run does)");
        return;
    };
    let html = page_of(example, dcl);
    let text = std::fs::read_to_string(&html).expect("page");
    assert!(!text.contains("<script src=") && !text.contains("<link "), "the page loads nothing from outside");

    // Start: ready, no errors, a painted canvas.
    let start = report(&chrome, &html, "at=0");
    let area = 900.0 * 760.0;
    assert!(start["painted"].as_f64().unwrap() > 0.1 * area, "{example}: canvas nearly blank: {start}");
    let (a, w) = screenshot(&chrome, &html, "at=0", &format!("{example}-start.png"));
    let (b, _) = screenshot(&chrome, &html, "at=0.5", &format!("{example}-middle.png"));
    let _ = screenshot(&chrome, &html, "at=1", &format!("{example}-end.png"));
    let (va, vb) = (view(&a, w), view(&b, w));
    let painted = va.iter().filter(|p| differs(**p, BACKGROUND)).count();
    assert!(painted as f64 > 0.1 * va.len() as f64, "{example}: start screenshot nearly blank ({painted} px)");
    let moved = va.iter().zip(&vb).filter(|(p, q)| differs(**p, **q)).count();
    assert!(moved > 2000, "{example}: start and middle differ in only {moved} px: the arm did not move");

    // Carried: the target rides rigidly in the hand from its grasp to its release (where
    // the schedule lets go of it, out of the cell), well away from where it stood.
    let t = &start["target"];
    assert!(t["grasped_at"].is_number(), "{example}: the target is never grasped: {start}");
    let grasped = t["grasped_at"].as_f64().unwrap();
    let carried_until = t["released_at"].as_f64().unwrap_or(start["duration"].as_f64().unwrap());
    assert!(carried_until > grasped + 0.2, "{example}: released {carried_until} s, grasped {grasped} s");
    // Just after the grasp: the hand barely moved, the object just taken.
    let at_grasp = report(&chrome, &html, &format!("t={}", grasped + 0.01));
    let end = report(&chrome, &html, &format!("t={}", carried_until - 0.01));
    let (g, e) = (&at_grasp["target"], &end["target"]);
    assert_eq!(e["visible"], true, "{example}: the target vanished before its release: {end}");
    if t["released_at"].is_number() {
        let gone = report(&chrome, &html, "at=1");
        assert_eq!(gone["target"]["visible"], false, "{example}: released, yet still drawn: {gone}");
    }
    let (dg, de) = (g["to_tcp"].as_f64().unwrap(), e["to_tcp"].as_f64().unwrap());
    assert!((dg - de).abs() < 2e-3, "{example}: target to TCP {dg} m at the grasp but {de} m at the end");
    assert!(de < 0.3, "{example}: the target is {de} m from the TCP");
    assert!(e["moved"].as_f64().unwrap() > 0.05, "{example}: the target did not leave its place: {end}");
    assert!(g["moved"].as_f64().unwrap() < 5e-3, "{example}: the target jumped at its grasp: {at_grasp}");
}

#[test]
fn box_lid_replays_in_chromium() {
    replay_checks("box_lid", "examples/box_lid.dcl");
}

#[test]
fn mesh_part_replays_in_chromium() {
    replay_checks("mesh_part", "examples/mesh_part.dcl");
}

/// A robot made of meshes: the book's Panda scenario ("Using your own robot"), with
/// Gepetto's example-robot-data from `../shared/robots/panda`.
#[test]
fn panda_with_mesh_links_replays_in_chromium() {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/robots/panda");
    if !robots.is_dir() {
        println!("skipped: {} is absent", robots.display());
        return;
    }
    let book = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("book/src/own-robot.md")).unwrap();
    let fence = "```dcl,link=robots:../shared/robots/panda\n";
    let start = book.find(fence).expect("the book's Panda scenario") + fence.len();
    let scenario = &book[start..start + book[start..].find("```").unwrap()];
    let dir = artefacts().join("panda");
    std::fs::create_dir_all(&dir).unwrap();
    let link = dir.join("robots");
    if std::fs::symlink_metadata(&link).is_err() {
        std::os::unix::fs::symlink(robots.canonicalize().unwrap(), &link).unwrap();
    }
    let dcl = dir.join("panda_can.dcl");
    std::fs::write(&dcl, scenario).unwrap();
    replay_checks("panda_can", dcl.to_str().unwrap());
}

/// The box_lid schedule as JSON, compiled once per call.
fn box_lid_schedule(name: &str) -> (PathBuf, Value) {
    let path = artefacts().join(name);
    let out = declutter(&["compile", "examples/box_lid.dcl", "--format", "json", "-o", path.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    (path, v)
}

#[test]
fn a_schedule_of_another_scenario_is_refused_like_verify_refuses_it() {
    let (path, mut v) = box_lid_schedule("foreign.json");
    v["scenario"] = "cans-5".into();
    std::fs::write(&path, v.to_string()).unwrap();
    let html = artefacts().join("foreign.html");
    let _ = std::fs::remove_file(&html);
    let out = declutter(&["show", "examples/box_lid.dcl", path.to_str().unwrap(), "-o", html.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("violation: ") && err.contains("cans-5"), "{err}");
    assert!(err.contains("not a schedule of this scenario; nothing written"), "{err}");
    assert!(!html.exists());
}

#[test]
fn a_schedule_that_does_not_verify_is_shown_with_its_violations_in_red() {
    // r2's first move bent down into the table: verify names the contacts and their times.
    let (path, mut v) = box_lid_schedule("unverified.json");
    let r2 = v["trajectories"].as_array_mut().unwrap().iter_mut().find(|t| t["robot"] == "r2").unwrap();
    let points = r2["points"].as_array_mut().unwrap();
    let moving =
        points.iter().position(|p| p["qd"].as_array().unwrap().iter().any(|x| x.as_f64() != Some(0.0))).unwrap();
    points[moving]["q"] = serde_json::json!([0.0, 2.2, 0.3, 0.0, 0.0, 0.0]);
    std::fs::write(&path, v.to_string()).unwrap();
    let html = artefacts().join("unverified.html");
    let out = declutter(&["show", "examples/box_lid.dcl", path.to_str().unwrap(), "-o", html.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(err.contains("violation: ") && err.contains("does not verify"), "{err}");
    let text = std::fs::read_to_string(&html).unwrap();
    assert!(text.contains(r#""status":"violations""#));
    let Some(chrome) = chromium() else {
        println!("skipped the browser part: no chromium on PATH");
        return;
    };
    let r = report(&chrome, &html, "at=0.9");
    assert_eq!(r["status"], "violations");
    assert!(r["marked"].as_u64().unwrap() >= 1, "no violation drawn at its place: {r}");
    let _ = screenshot(&chrome, &html, "at=0.9", "unverified.png");
}

#[test]
fn cans_5_page_and_the_cell_alone_stay_small() {
    let html = page("cans_5");
    assert!(std::fs::metadata(&html).unwrap().len() < MAX_PAGE_BYTES);
    let cell = artefacts().join("cell.html");
    let out = declutter(&["show", "examples/box_lid.dcl", "-o", cell.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&cell).unwrap();
    assert!(text.contains(r#""status":"cell""#) && text.contains(r#""actions":[]"#));
    if let Some(chrome) = chromium() {
        let r = report(&chrome, &html, "at=0.5");
        assert!(r["painted"].as_f64().unwrap() > 0.1 * 900.0 * 760.0, "{r}");
        let r = report(&chrome, &cell, "");
        assert_eq!(r["duration"], 0.0);
    }
}

/// Every picture the book shows from `figures/generated/` (drawn by
/// `book/tools/render_pictures.sh`) has a committed copy to fall back on, and the script
/// draws it.
#[test]
fn book_pictures_have_committed_copies_and_one_command_draws_them() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let script = std::fs::read_to_string(root.join("book/tools/render_pictures.sh")).unwrap();
    let mut seen = 0;
    for page in std::fs::read_dir(root.join("book/src")).unwrap().flatten() {
        let text = std::fs::read_to_string(page.path()).unwrap_or_default();
        for part in text.split("<img src=\"figures/generated/").skip(1) {
            let name = &part[..part.find(".png\"").expect("a PNG")];
            let fallback = format!("this.src='figures/replay/{name}.png'");
            assert!(part[..part.find('>').unwrap()].contains(&fallback), "{name}: no fallback in {:?}", page.path());
            assert!(root.join(format!("book/src/figures/replay/{name}.png")).is_file(), "{name}.png is not committed");
            assert!(script.contains(&format!("\nshot {name} ")), "render_pictures.sh does not draw {name}");
            seen += 1;
        }
    }
    assert!(seen >= 4, "the book shows {seen} pictures");
}
