//! The paper's parametric and excitation studies (Secs 6 and 8, Figs 15-18, 24-29), each
//! computed from the model, never tabulated: see [`run_study`].

pub mod figures;
