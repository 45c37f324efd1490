//! Reference data files: their formats, read and validated (values stated in a source, curves
//! digitised from the paper's figures). No checks here: the experiment files validate their
//! references against these, and the checks compare with them.

pub mod digitised;
pub mod files;
pub mod import;
pub mod values;
