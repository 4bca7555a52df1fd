//! The end-to-end tests and the verification ladder, one test binary (each integration
//! test binary links the whole dependency tree). A new test file is a module here.

mod architecture;
mod catenary_docs;
mod damping_law;
mod damping_laws;
mod diagnose;
mod diagnose_joint;
mod diagnose_length;
mod diagnose_mesh;
mod forced;
mod forced_spring;
mod frc_check;
mod marc_interchange;
mod nonlinear;
mod paper_spring;
mod readme;
mod reduction;
mod results;
mod shared_data;
mod spring_design;
mod spring_input;
mod transient;
mod truth;
mod tuner;
mod verification;
