use super::*;

/// Every kind the message lists is one the parser knows (its error, if any, is about
/// something else than the kind's name), and an unknown one lists them all.
#[test]
fn the_listed_check_kinds_are_the_parsed_ones() {
    let dir = std::env::temp_dir();
    let files = Files::new(&dir);
    let at = At { path: Path::new("x.toml"), i: 0, n: 3, case_ids: &[], analysis: &Analysis::Modal };
    let raw = |kind: &str| -> RawCheck {
        let table: toml::Table = toml::from_str(&format!("kind = \"{kind}\"")).expect("toml");
        table.try_into().expect("a raw check")
    };
    for k in CHECK_KINDS {
        if let Err(e) = kind_of(&at, &raw(k), &files) {
            assert!(!e.to_string().contains("allowed kinds"), "{k}: {e}");
        }
    }
    let e = kind_of(&at, &raw("nope"), &files).err().map(|e| e.to_string()).unwrap_or_default();
    assert!(CHECK_KINDS.iter().all(|k| e.contains(&format!("\"{k}\""))), "{e}");
}
