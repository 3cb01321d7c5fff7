//! The frequency windows of the residual-energy tests: around Omega = 1/3, 1/2, 2/3 (super-
//! harmonic resonances excited by the 3rd and 2nd harmonics of the excitation), 1 (primary) and
//! 2 (the subharmonic of a parametric excitation at twice the natural frequency).

/// A window Omega in [c (1 - w), c (1 + w)].
#[derive(Clone, Debug, serde::Serialize)]
pub struct Window {
    pub label: &'static str,
    pub centre: f64,
    pub lo: f64,
    pub hi: f64,
}

/// Relative half width of every window: three to four points of a 50 rpm grid near resonance
/// of Munro's rig, and narrower than the spacing of the windows (1/2 to 2/3 is 29%).
pub const HALF_WIDTH: f64 = 0.05;

/// The five windows.
pub fn windows() -> Vec<Window> {
    [
        ("1/3", 1.0 / 3.0),
        ("1/2", 0.5),
        ("2/3", 2.0 / 3.0),
        ("1", 1.0),
        ("2", 2.0),
    ]
    .iter()
    .map(|&(label, c)| Window {
        label,
        centre: c,
        lo: c * (1.0 - HALF_WIDTH),
        hi: c * (1.0 + HALF_WIDTH),
    })
    .collect()
}

impl Window {
    /// Whether Omega lies in the window.
    pub fn contains(&self, omega: f64) -> bool {
        omega >= self.lo && omega <= self.hi
    }
}
