//! The model beyond the paper (docs/model.md section 2.2-2.3): containers whose motion is not
//! vertical, and supports that move instead of a force. One test binary.

#[path = "../common/mod.rs"]
mod common;

mod base;
mod horizontal;
