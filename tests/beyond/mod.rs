//! The model beyond the paper (docs/model.md section 2.2-2.3): containers whose motion is not
//! vertical, and supports that move instead of a force.

mod base;
mod horizontal;
