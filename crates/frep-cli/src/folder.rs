//! Writing an export's files into a folder: `frep render --views` (a view
//! set) and `frep slices` (a slice stack).
//!
//! frep-render produces the files as names and bytes ([`OutFile`]); only
//! the command line writes folders.

use std::path::Path;

use anyhow::Context;
use frep_render::OutFile;

/// Writes `files` into `dir`, creating it if needed; an existing file of
/// the same name is replaced.
pub fn write_folder(dir: &Path, files: &[OutFile]) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for f in files {
        let path = dir.join(&f.name);
        std::fs::write(&path, &f.bytes)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}
