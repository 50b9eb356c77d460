//! SRDF text -> the link pairs its `<disable_collisions>` exclude from self-collision
//! (the pairs MoveIt's setup assistant found adjacent, never or always in contact).
//! Groups, states and end effectors are not used.

/// One `<disable_collisions link1=".." link2=".."/>`, with its 1-based line.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DisabledPair {
    pub a: String,
    pub b: String,
    pub line: u32,
}

/// The disabled pairs, or (why, line) when the text is not an SRDF.
pub(crate) fn disabled_pairs(text: &str) -> Result<Vec<DisabledPair>, (String, u32)> {
    let doc = roxmltree::Document::parse(text).map_err(|e| (e.to_string(), e.pos().row))?;
    let root = doc.root_element();
    if root.tag_name().name() != "robot" {
        let line = doc.text_pos_at(root.range().start).row;
        return Err((format!("the root element is <{}>, not <robot>", root.tag_name().name()), line));
    }
    let mut out = Vec::new();
    for n in root.children().filter(|n| n.is_element() && n.tag_name().name() == "disable_collisions") {
        let line = doc.text_pos_at(n.range().start).row;
        match (n.attribute("link1"), n.attribute("link2")) {
            (Some(a), Some(b)) => out.push(DisabledPair { a: a.to_string(), b: b.to_string(), line }),
            _ => return Err(("<disable_collisions> needs both `link1` and `link2`".to_string(), line)),
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_with_lines_and_located_errors() {
        let text = "<robot name=\"r\">\n  <group name=\"arm\"/>\n  <disable_collisions link1=\"a\" link2=\"b\" reason=\"Adjacent\"/>\n</robot>\n";
        assert_eq!(disabled_pairs(text).unwrap(), [DisabledPair { a: "a".into(), b: "b".into(), line: 3 }]);
        assert_eq!(disabled_pairs("<robot>\n<disable_collisions link1=\"a\"/>\n</robot>").unwrap_err().1, 2);
        assert_eq!(disabled_pairs("<robot>\n<oops>\n</robot>").unwrap_err().1, 3);
    }
}
