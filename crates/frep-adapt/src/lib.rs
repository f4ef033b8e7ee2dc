//! # frep-adapt (being written)
