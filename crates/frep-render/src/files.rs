//! [`OutFile`]: one file of an export (a view set, a slice stack), as a
//! name and its bytes.
//!
//! The library produces files; it never writes them. The caller decides
//! where they go: the CLI writes them into a folder, a server could zip or
//! serve them.

/// A file's name (no folder) and its bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutFile {
    /// The file name, e.g. `view_003.jpg`.
    pub name: String,
    /// The file's contents.
    pub bytes: Vec<u8>,
}

impl OutFile {
    /// A file named `name` holding `bytes`.
    pub fn new(name: impl Into<String>, bytes: Vec<u8>) -> OutFile {
        OutFile {
            name: name.into(),
            bytes,
        }
    }
}
