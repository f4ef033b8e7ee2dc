//! The committed TypeScript declarations match the Rust wire types.

use std::path::PathBuf;

#[test]
fn web_wire_ts_is_fresh() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../web/src/wire.ts");
    let want = frep_wire::typescript();
    if std::env::var_os("FREP_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &want).unwrap();
        return;
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "{} is stale: run `FREP_BLESS=1 cargo test -p frep-wire` and commit it",
        path.display()
    );
}
