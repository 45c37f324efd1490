//! Every integration test of shotdamp in one binary (`cargo test --release --locked`; one
//! file a module: `cargo test --release --locked --test all -- MODULE::` runs one file's
//! tests). One binary links the library once: the suite builds in a fraction of the time 35
//! binaries took. The helpers every file may use are in `common`.

mod common;

mod adaptive;
mod beyond;
mod bounded;
mod browser;
mod campaign;
mod certify;
mod chunking;
mod cli;
mod column;
mod contract;
mod design;
mod design_seismic;
mod design_store;
mod explore;
mod extending;
mod fe;
mod follow;
mod fuzz;
mod ground;
mod ground_response;
mod hostile;
mod impulse;
mod irregular;
mod joint;
mod library;
mod models;
mod newton;
mod opensees;
mod periodic;
mod readings;
mod record;
mod reliability;
mod repeated;
mod report_budget;
mod report_files;
mod restitution;
mod review;
mod scan;
mod shards;
mod simulator;
mod size;
mod soft_contact;
mod steady_orbit;
mod study;
mod sweep;
mod texts;
mod torus;
mod vary;
