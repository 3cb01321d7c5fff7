//! The dimensionless gear-pair model, written from Kahraman & Singh (1990) eq. 3a-3c and eq. 20
//! and geardyn's design notes (section 1), not from geardyn's source:
//!
//!   q'' + 2 zeta q' + k(t) f(q) = F_m + F_aT sin(W t + psi_T)
//!                                 + W^2 F_ah sin(W t) + (2W)^2 F_ah2 sin(2 W t + phi_2)
//!   k(t) = 1 + eps cos(W t + psi_k)
//!   f(q) = q - 1 (q > 1), 0 (|q| <= 1), q + 1 (q < -1)
//!
//! or, as an effect outside geardyn's library, a contact force c |q -+ 1|^n in place of q -+ 1.
//!
//! with t = omega_n t_bar, q = q_bar / b (b = half backlash), W = mesh frequency / natural
//! frequency. The dynamic transmission error is x = q + e/b with
//! e/b = F_ah sin(W t) + F_ah2 sin(2 W t + phi_2); its peak-to-peak times b is `dte_pp_um`.

/// Everything the right-hand side needs at one speed and one load.
#[derive(Clone, Debug)]
pub struct Excitation {
    pub zeta: f64,
    /// Mesh frequency over natural frequency, Omega_h.
    pub omega: f64,
    /// Mean load F_m = F / (b k_h).
    pub fm: f64,
    /// First STE harmonic amplitude over b, F_ah = e_1 / b.
    pub fah: f64,
    /// Second STE harmonic amplitude over b (r2 F_ah) and its phase (rad).
    pub fah2: f64,
    pub phi2: f64,
    /// External force at the mesh frequency (torque ripple), F_aT = ratio F_m(design), phase (rad).
    pub fat: f64,
    pub psi_t: f64,
    /// Mesh stiffness variation k = 1 + eps cos(W t + psi_k).
    pub eps: f64,
    pub psi_k: f64,
    pub contact: Contact,
}

/// The contact force c |d|^n sign(d) of a penetration d = q - 1 (or q + 1 on the back flank);
/// n = 1, c = 1 is eq. 3c's linear law. For n > 1 it is smooth through d = 0 (slope 0), so a
/// region's branch extended past its boundary stays smooth for the integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    pub c: f64,
    pub n: f64,
}

impl Contact {
    pub const LINEAR: Contact = Contact { c: 1.0, n: 1.0 };

    /// The law of exponent `n` whose local stiffness is 1 at the mean deflection of the
    /// mean force `fm_design`: c n d^(n-1) = 1 and c d^n = fm_design give d = n fm_design.
    pub fn stiff_at(n: f64, fm_design: f64) -> Contact {
        Contact {
            c: (n * fm_design).powf(1.0 - n) / n,
            n,
        }
    }

    /// Force and its derivative at penetration d.
    #[inline]
    pub fn force(&self, d: f64) -> (f64, f64) {
        if self.n == 1.0 {
            return (self.c * d, self.c);
        }
        let a = d.abs();
        (
            self.c * a.powf(self.n) * d.signum(),
            self.c * self.n * a.powf(self.n - 1.0),
        )
    }

    /// The static penetration under a mean force fm: (fm / c)^(1/n).
    pub fn deflection(&self, fm: f64) -> f64 {
        (fm / self.c).powf(1.0 / self.n)
    }
}

impl Excitation {
    /// The region's branch of the contact force and its slope in q (0 in the free region).
    #[inline]
    fn contact_force(&self, q: f64, region: i8) -> (f64, f64) {
        match region {
            1 => self.contact.force(q - 1.0),
            -1 => self.contact.force(q + 1.0),
            _ => (0.0, 0.0),
        }
    }

    /// e(t)/b: the static transmission error in half backlashes.
    #[inline]
    pub fn ste(&self, t: f64) -> f64 {
        let wt = self.omega * t;
        let mut e = self.fah * wt.sin();
        if self.fah2 != 0.0 {
            e += self.fah2 * (2.0 * wt + self.phi2).sin();
        }
        e
    }

    /// d(e/b)/dt.
    #[inline]
    pub fn ste_dot(&self, t: f64) -> f64 {
        let wt = self.omega * t;
        let mut d = self.omega * self.fah * wt.cos();
        if self.fah2 != 0.0 {
            d += 2.0 * self.omega * self.fah2 * (2.0 * wt + self.phi2).cos();
        }
        d
    }

    /// Right-hand side force F(t) of eq. 20 (mean load, torque ripple, STE terms).
    #[inline]
    pub fn force(&self, t: f64) -> f64 {
        let wt = self.omega * t;
        let w2 = self.omega * self.omega;
        let mut f = self.fm + w2 * self.fah * wt.sin();
        if self.fah2 != 0.0 {
            f += 4.0 * w2 * self.fah2 * (2.0 * wt + self.phi2).sin();
        }
        if self.fat != 0.0 {
            f += self.fat * (wt + self.psi_t).sin();
        }
        f
    }

    /// Time-varying mesh stiffness k(t).
    #[inline]
    pub fn stiffness(&self, t: f64) -> f64 {
        if self.eps == 0.0 {
            1.0
        } else {
            1.0 + self.eps * (self.omega * t + self.psi_k).cos()
        }
    }

    /// q'' with the dead-zone function of the given region (+1: q > 1 contact, 0: free,
    /// -1: back contact). Inside one integration segment the region's own (linear) branch of f is
    /// used, extended smoothly past the boundary, so the integrator sees a smooth right-hand side;
    /// the segment is stopped at the boundary crossing (event) and the region switched there.
    #[inline]
    pub fn accel(&self, t: f64, q: f64, v: f64, region: i8) -> f64 {
        let (fq, _) = self.contact_force(q, region);
        let k = if fq == 0.0 { 1.0 } else { self.stiffness(t) };
        self.force(t) - 2.0 * self.zeta * v - k * fq
    }
}

impl Excitation {
    /// Mesh force 2 zeta q' + k(t) f(q) (units of b k_h) with the region's branch of f; the
    /// dynamic factor is its largest value over the steady state divided by F_m (paper Sec. 7:
    /// D_L = (2 zeta q' + f(q)) / F_m).
    #[inline]
    pub fn mesh_force(&self, t: f64, q: f64, v: f64, region: i8) -> f64 {
        let (fq, _) = self.contact_force(q, region);
        let k = if fq == 0.0 { 1.0 } else { self.stiffness(t) };
        2.0 * self.zeta * v + k * fq
    }

    /// d/dt of the mesh force along a trajectory of the region: 2 zeta q'' + k f'(q) q' + k' f(q).
    #[inline]
    pub fn mesh_force_dot(&self, t: f64, q: f64, v: f64, region: i8) -> f64 {
        let a = self.accel(t, q, v, region);
        let (fq, dfq) = self.contact_force(q, region);
        let mut d = 2.0 * self.zeta * a;
        if region != 0 {
            d += self.stiffness(t) * dfq * v;
            if self.eps != 0.0 {
                d -= self.eps * self.omega * (self.omega * t + self.psi_k).sin() * fq;
            }
        }
        d
    }
}

/// The region of eq. 3c a state belongs to.
pub fn region_of(q: f64, v: f64) -> i8 {
    if q > 1.0 || (q == 1.0 && v > 0.0) {
        1
    } else if q < -1.0 || (q == -1.0 && v < 0.0) {
        -1
    } else {
        0
    }
}
