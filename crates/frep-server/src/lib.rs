//! # frep-server (being written)
