//! The example models, embedded in the binary, and their seeding into a new
//! store.
//!
//! The files of `examples/` are compiled in with `include_str!` (one line
//! per file below), so `frep serve` works from any working directory. A
//! test checks that this list is exactly the folder's `*.hf` files, so a new
//! example cannot be forgotten.
//!
//! Seeding happens once per data folder.
//! 1. On the first start, every example becomes a model of
//!    [`EXAMPLES_OWNER`], named after its file (without `.hf`). It gets
//!    version 1 with the message "example".
//! 2. Then a marker file (`examples-seeded`) is written in the data folder.
//!
//! A later start finds the marker and adds nothing, so examples the user
//! deleted stay deleted. Should the marker be missing after a crash between
//! the two steps, the example models themselves are found instead.

use std::path::Path;

use frep_store::{Store, StoreError};
use frep_wire::CreateModel;

/// The owner of the seeded example models.
pub const EXAMPLES_OWNER: &str = "examples";

/// Every example: file name (without `.hf`) and source.
pub const EXAMPLES: &[(&str, &str)] = &[
    (
        "android_robot",
        include_str!("../../../examples/android_robot.hf"),
    ),
    (
        "closed_cylinder",
        include_str!("../../../examples/closed_cylinder.hf"),
    ),
    (
        "complex_hemisphere",
        include_str!("../../../examples/complex_hemisphere.hf"),
    ),
    ("cylinder", include_str!("../../../examples/cylinder.hf")),
    ("m1_sphere", include_str!("../../../examples/m1_sphere.hf")),
    (
        "m2_spheres100",
        include_str!("../../../examples/m2_spheres100.hf"),
    ),
    ("m3_gyroid", include_str!("../../../examples/m3_gyroid.hf")),
    (
        "m4_rblend10",
        include_str!("../../../examples/m4_rblend10.hf"),
    ),
    ("sake_pot", include_str!("../../../examples/sake_pot.hf")),
    (
        "semi_sphere",
        include_str!("../../../examples/semi_sphere.hf"),
    ),
    ("sphere", include_str!("../../../examples/sphere.hf")),
];

/// The marker file of a seeded data folder.
pub const SEEDED_MARKER: &str = "examples-seeded";

/// Seeds the examples into `store`, unless `data_dir` has the marker or the
/// store has a model owned by [`EXAMPLES_OWNER`]. Answers how many models it
/// created.
pub fn seed(store: &dyn Store, data_dir: &Path) -> Result<usize, SeedError> {
    let marker = data_dir.join(SEEDED_MARKER);
    if marker.exists() {
        return Ok(0);
    }
    let models = store.list_models()?;
    let mut created = 0;
    if !models.iter().any(|m| m.owner == EXAMPLES_OWNER) {
        for (name, source) in EXAMPLES {
            let req = CreateModel {
                name: name.to_string(),
                source: source.to_string(),
                params: Vec::new(),
                message: "example".to_string(),
            };
            match store.create_model(EXAMPLES_OWNER, req) {
                Ok(_) => created += 1,
                // An example over a configured limit is left out, not a
                // reason to refuse to start.
                Err(e @ (StoreError::Limit { .. } | StoreError::Invalid(_))) => {
                    tracing::warn!(example = name, "example not loaded: {e}");
                }
                Err(e) => return Err(e.into()),
            }
        }
    }
    std::fs::write(
        &marker,
        "the example models were loaded into this folder's store\n",
    )?;
    Ok(created)
}

/// Why seeding failed.
#[derive(Debug, thiserror::Error)]
pub enum SeedError {
    /// The store refused.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// The marker could not be written.
    #[error("writing the seed marker: {0}")]
    Io(#[from] std::io::Error),
}

/// The `-- description:` line of a source, if it has one.
pub fn description(source: &str) -> Option<&str> {
    source
        .lines()
        .take_while(|l| l.trim_start().starts_with("--"))
        .find_map(|l| l.trim_start().strip_prefix("-- description:"))
        .map(str::trim)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_list_is_the_examples_folder() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples");
        let mut on_disk: Vec<(String, String)> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "hf"))
            .map(|p| {
                let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
                (stem, std::fs::read_to_string(&p).unwrap())
            })
            .collect();
        on_disk.sort();
        let embedded: Vec<(String, String)> = EXAMPLES
            .iter()
            .map(|(n, s)| (n.to_string(), s.to_string()))
            .collect();
        assert_eq!(
            embedded.iter().map(|e| &e.0).collect::<Vec<_>>(),
            on_disk.iter().map(|e| &e.0).collect::<Vec<_>>(),
            "add or remove the example in src/examples.rs"
        );
        assert_eq!(embedded, on_disk);
    }

    #[test]
    fn every_example_has_a_description() {
        for (name, source) in EXAMPLES {
            let d = description(source).unwrap_or_default();
            assert!(!d.is_empty(), "{name} has no `-- description:` line");
        }
        assert_eq!(description("-- bounds: 1\nx"), None);
    }
}
