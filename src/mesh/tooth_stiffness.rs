//! Stiffness of one tooth pair along the path of contact by the potential-energy method.
//!
//! Each tooth is a non-uniform cantilever on the root circle, loaded by the contact force F
//! along the line of action at angle alpha_1 to the normal of the tooth's centre line
//! (Yang & Lin, ASME J. Mech. Trans. Autom. Des. 109, 1987; Tian, MSc thesis, U. Alberta, 2004;
//! Chaari, Fakhfakh & Haddar, Eur. J. Mech. A/Solids 28, 2009). With y along the centre line
//! from the gear's centre, x(y) the half thickness, the contact point (x_c, y_c), section area
//! A = 2 x L, second moment I = (2x)^3 L / 12 and G = E / (2 (1 + nu)):
//!
//! ```text
//! 1/k_b = integral_{y_f}^{y_c} ((y_c - y) cos(alpha_1) - x_c sin(alpha_1))^2 / (E I) dy   bending
//! 1/k_s = integral 1.2 cos^2(alpha_1) / (G A) dy                                         shear
//! 1/k_a = integral sin^2(alpha_1) / (E A) dy                                             axial
//! 1/k_h = 4 (1 - nu^2) / (pi E L)                            Hertzian contact (Yang & Lin)
//! 1/k_f = cos^2(alpha_1) / (E L) (L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2(alpha_1)))
//! ```
//!
//! The last line is the fillet-foundation flexibility of Sainsot, Velex & Duverger (ASME J.
//! Mech. Des. 126, 2004): u_f is the distance along the centre line from the root circle to
//! where the line of action crosses it, S_f = 2 r_f theta_f the root arc of the tooth between
//! its fillets ([`GearBody::root_half_angle`]), and each
//! of L*, M*, P*, Q* is A/theta_f^2 + B h_f^2 + C h_f/theta_f + D/theta_f + E h_f + F with
//! h_f = r_f / r_bore and the coefficients of their Table 1 ([`SAINSOT`]).
//!
//! For an involute point at profile pressure angle phi (tan(phi) = roll distance / r_b), the
//! half angle of the tooth is psi = alpha_2 - inv(phi) and alpha_1 = tan(phi) - alpha_2
//! (alpha_2 the half tooth angle on the base circle). Below the base circle (when r_f < r_b)
//! the flank is taken as straight and radial-parallel, of the base-circle thickness (the usual
//! simplification, e.g. Ma et al., Mech. Syst. Signal Process. 70-71, 2016, sec. 2). The
//! integrals are evaluated by composite Simpson rules.
//!
//! The pair's stiffness is k = 1 / (1/k_h + sum over both teeth of (1/k_b + 1/k_s + 1/k_a +
//! 1/k_f)). It does not depend on the load (linear Hertz term), so load enters the mesh only
//! through load sharing and contact loss ([`super::ste`]).

use super::geometry::{involute, GearBody, GearPairGeometry};
use serde::Serialize;

/// Sainsot, Velex & Duverger (2004), Table 1: the coefficients A..F of L*, M*, P*, Q*.
pub const SAINSOT: [[f64; 6]; 4] = [
    [-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045],
    [60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086],
    [-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236],
    [
        -6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904,
    ],
];

/// Intervals of each composite Simpson rule (even).
const SIMPSON_INTERVALS: usize = 400;

/// Compliances (m/N) of one tooth loaded at one point of its flank.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ToothCompliance {
    /// Bending, 1/k_b.
    pub bending: f64,
    /// Shear, 1/k_s.
    pub shear: f64,
    /// Axial compression, 1/k_a.
    pub axial: f64,
    /// Fillet foundation (Sainsot et al. 2004), 1/k_f.
    pub foundation: f64,
}

impl ToothCompliance {
    /// Sum of the four terms, m/N.
    pub fn total(&self) -> f64 {
        self.bending + self.shear + self.axial + self.foundation
    }
}

/// Stiffness of one tooth pair at one contact position.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PairStiffness {
    /// Roll distance s from T1 on the line of action, metres.
    pub roll_m: f64,
    /// Pinion tooth compliances.
    pub pinion: ToothCompliance,
    /// Gear tooth compliances.
    pub gear: ToothCompliance,
    /// Hertzian contact compliance 1/k_h, m/N.
    pub hertz: f64,
    /// Pair stiffness k = 1 / (sum of all compliances), N/m.
    pub stiffness_n_per_m: f64,
}

/// Composite Simpson rule of `f` over [a, b] with `n` (even) intervals.
fn simpson(a: f64, b: f64, n: usize, f: impl Fn(f64) -> f64) -> f64 {
    if b <= a {
        return 0.0;
    }
    let h = (b - a) / n as f64;
    let mut sum = f(a) + f(b);
    for i in 1..n {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * f(a + i as f64 * h);
    }
    sum * h / 3.0
}

/// Hertzian contact compliance of a line contact, 4 (1 - nu^2) / (pi E L) (Yang & Lin 1987),
/// m/N.
pub fn hertz_compliance(geo: &GearPairGeometry) -> f64 {
    let nu = geo.poisson_ratio;
    4.0 * (1.0 - nu * nu) / (std::f64::consts::PI * geo.youngs_modulus_pa * geo.face_width_m)
}

/// Point (x, y) of the involute flank at profile pressure angle phi: half thickness x and
/// distance y along the centre line from the gear's centre.
fn flank_point(body: &GearBody, phi: f64) -> (f64, f64) {
    let r = body.base_radius_m / phi.cos();
    let psi = body.half_base_angle - involute(phi);
    (r * psi.sin(), r * psi.cos())
}

/// Sainsot's polynomial X* = A/theta_f^2 + B h_f^2 + C h_f/theta_f + D/theta_f + E h_f + F.
fn sainsot(c: &[f64; 6], theta_f: f64, h_f: f64) -> f64 {
    c[0] / (theta_f * theta_f)
        + c[1] * h_f * h_f
        + c[2] * h_f / theta_f
        + c[3] / theta_f
        + c[4] * h_f
        + c[5]
}

/// Compliances of `body`'s tooth loaded where the line of action is `roll` metres from the
/// body's own base-circle tangency point (tan(phi) = roll / r_b).
pub fn tooth_compliance(geo: &GearPairGeometry, body: &GearBody, roll: f64) -> ToothCompliance {
    let e = geo.youngs_modulus_pa;
    let l = geo.face_width_m;
    let g = e / (2.0 * (1.0 + geo.poisson_ratio));
    let rb = body.base_radius_m;
    let a2 = body.half_base_angle;
    let phi_c = (roll / rb).atan();
    let alpha1 = phi_c.tan() - a2;
    let (xc, yc) = flank_point(body, phi_c);
    let (ca, sa) = (alpha1.cos(), alpha1.sin());
    // Integrands per unit dy at half thickness x and height y.
    let bend = |x: f64, y: f64| {
        let arm = (yc - y) * ca - xc * sa;
        arm * arm * 12.0 / (e * 8.0 * x * x * x * l)
    };
    let shear = |x: f64| 1.2 * ca * ca / (g * 2.0 * x * l);
    let axial = |x: f64| sa * sa / (e * 2.0 * x * l);
    let rf = body.root_radius_m;
    let n = SIMPSON_INTERVALS;
    let (mut cb, mut cs, mut cax) = (0.0, 0.0, 0.0);
    // Involute part: from the lower end of the involute (base circle, or the root circle when
    // it lies above the base circle) to the contact point, integrated over phi with dy/dphi.
    let phi_low = if rf > rb { (rb / rf).acos() } else { 0.0 };
    let dy_dphi = |phi: f64| {
        let r = rb / phi.cos();
        let psi = a2 - involute(phi);
        let t = phi.tan();
        rb * phi.sin() / (phi.cos() * phi.cos()) * psi.cos() + r * psi.sin() * t * t
    };
    let over_phi = |f: &dyn Fn(f64, f64) -> f64| {
        simpson(phi_low, phi_c, n, |phi| {
            let (x, y) = flank_point(body, phi);
            f(x, y) * dy_dphi(phi)
        })
    };
    cb += over_phi(&bend);
    cs += over_phi(&|x, _| shear(x));
    cax += over_phi(&|x, _| axial(x));
    // Straight part between the root circle and the base circle (r_f < r_b only).
    if rf < rb {
        let xb = rb * a2.sin();
        let yb = rb * a2.cos();
        let yf = (rf * rf - xb * xb).max(0.0).sqrt();
        cb += simpson(yf, yb, n, |y| bend(xb, y));
        cs += (yb - yf) * shear(xb);
        cax += (yb - yf) * axial(xb);
    }
    // Fillet foundation (Sainsot et al. 2004): the tooth's root spans 2 theta_f on the root
    // circle, fillets included; u_f runs along the centre line from the root circle to where
    // the line of action crosses it.
    let theta_f = body.root_half_angle;
    let s_f = 2.0 * rf * theta_f;
    let h_f = rf / body.bore_radius_m;
    let [lc, mc, pc, qc] = SAINSOT.map(|c| sainsot(&c, theta_f, h_f));
    let u = (yc - xc * alpha1.tan() - rf) / s_f;
    let foundation =
        ca * ca / (e * l) * (lc * u * u + mc * u + pc * (1.0 + qc * alpha1.tan().powi(2)));
    ToothCompliance {
        bending: cb,
        shear: cs,
        axial: cax,
        foundation,
    }
}

/// Stiffness of the tooth pair in contact at roll distance `s` from T1 (pinion roll s, gear
/// roll T1T2 - s).
pub fn pair_stiffness(geo: &GearPairGeometry, s: f64) -> PairStiffness {
    let pinion = tooth_compliance(geo, &geo.pinion, s);
    let gear = tooth_compliance(geo, &geo.gear, geo.line_of_action_length() - s);
    let hertz = hertz_compliance(geo);
    PairStiffness {
        roll_m: s,
        pinion,
        gear,
        hertz,
        stiffness_n_per_m: 1.0 / (hertz + pinion.total() + gear.total()),
    }
}

/// Pair stiffness tabulated at `n` (>= 2) equally spaced points over the path of contact
/// [s_A, s_E], for interpolation by [`StiffnessTable::at`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StiffnessTable {
    /// The tabulated points, in increasing roll distance.
    pub points: Vec<PairStiffness>,
}

impl StiffnessTable {
    /// Tabulate [`pair_stiffness`] at `n` points from s_A to s_E.
    pub fn new(geo: &GearPairGeometry, n: usize) -> Self {
        let n = n.max(2);
        let (a, b) = (geo.start_of_contact(), geo.end_of_contact());
        StiffnessTable {
            points: (0..n)
                .map(|i| pair_stiffness(geo, a + (b - a) * i as f64 / (n - 1) as f64))
                .collect(),
        }
    }

    /// Pair stiffness (N/m) at roll distance s, linearly interpolated (clamped to the path).
    pub fn at(&self, s: f64) -> f64 {
        let p = &self.points;
        let (a, b) = (p[0].roll_m, p[p.len() - 1].roll_m);
        let u = ((s - a) / (b - a)).clamp(0.0, 1.0) * (p.len() - 1) as f64;
        let i = (u.floor() as usize).min(p.len() - 2);
        let w = u - i as f64;
        p[i].stiffness_n_per_m * (1.0 - w) + p[i + 1].stiffness_n_per_m * w
    }
}
