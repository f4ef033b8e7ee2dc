//! # frep-artefact (being written)
