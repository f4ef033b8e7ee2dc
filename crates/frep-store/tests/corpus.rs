//! Real HyperFun models written by others (`/work/shared/hyperfun/corpus`,
//! when present): stored byte for byte, and their diffs against an edited
//! copy reconstruct both texts with consistent line numbers.

mod common;

use common::{create, edit, memory};
use frep_store::{DiffKind, Store};

const CORPUS: &str = "/work/shared/hyperfun/corpus";

/// Drops every third line and appends a comment: removals and an addition.
fn edited(source: &str) -> String {
    let mut out: String = source
        .lines()
        .enumerate()
        .filter(|(i, _)| i % 3 != 1)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    out.push_str("-- edited\n");
    out
}

#[test]
fn corpus_round_trips_and_diffs() {
    let Ok(dir) = std::fs::read_dir(CORPUS) else {
        eprintln!("{CORPUS} absent: nothing to check");
        return;
    };
    let s = memory();
    let mut checked = 0;
    for entry in dir {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "hf") {
            continue;
        }
        let bytes = std::fs::read(&path).unwrap();
        let source = String::from_utf8_lossy(&bytes).into_owned();
        let name = path.file_stem().unwrap().to_string_lossy();
        let name: String = name.chars().take(100).collect();
        let id = create(&s, "corpus", &name, &source).model.id;
        let new = edited(&source);
        s.save_version(&id, "corpus", edit(&new)).unwrap();
        assert_eq!(s.get_version(&id, Some(1)).unwrap().source, source);

        let d = s.diff(&id, 1, 2).unwrap();
        let old_side: Vec<(u32, &str)> = d
            .lines
            .iter()
            .filter(|l| l.kind != DiffKind::Added)
            .map(|l| (l.old_line.unwrap(), l.text.as_str()))
            .collect();
        let new_side: Vec<(u32, &str)> = d
            .lines
            .iter()
            .filter(|l| l.kind != DiffKind::Removed)
            .map(|l| (l.new_line.unwrap(), l.text.as_str()))
            .collect();
        let expect_old: Vec<(u32, &str)> = source
            .lines()
            .enumerate()
            .map(|(i, l)| (i as u32 + 1, l.strip_suffix('\r').unwrap_or(l)))
            .collect();
        let expect_new: Vec<(u32, &str)> = new
            .lines()
            .enumerate()
            .map(|(i, l)| (i as u32 + 1, l.strip_suffix('\r').unwrap_or(l)))
            .collect();
        assert_eq!(old_side, expect_old, "{}", path.display());
        assert_eq!(new_side, expect_new, "{}", path.display());
        assert!(d.lines.iter().any(|l| l.kind == DiffKind::Added));
        checked += 1;
    }
    assert!(checked > 0, "no .hf file in {CORPUS}");
}
