//! The file layer: what an experiment file may say, before anything is checked against
//! physics. The TOML types with their keys ([`raw`]: `deny_unknown_fields` names a misspelt
//! key), reading a file with the `extends` chain and model files merged ([`read`]); its
//! errors name the file (and the line and column of a syntax error). The typed, validated
//! setup is one function away: `validate` of the experiment room turns a [`raw::RawExperiment`]
//! into an `Experiment` ([`super::loader`] runs both).

pub mod grid;
pub mod raw;
pub mod raw_design;
pub mod raw_ground;
pub mod raw_study;
pub mod read;
