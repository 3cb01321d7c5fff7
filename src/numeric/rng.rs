//! A small seeded random number generator for synthetic data and bootstrap replicates
//! (SplitMix64 with Box-Muller), so that a data set or a bootstrap is reproducible from its
//! recorded seed without extra dependencies.

/// SplitMix64 (Steele, Lea & Flood 2014) with Gaussian deviates by Box-Muller.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

impl Rng {
    /// Generator from a seed.
    pub fn new(seed: u64) -> Self {
        Rng { state: seed }
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform deviate in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal deviate.
    pub fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }

    /// Gamma(shape, 1) deviate by Marsaglia & Tsang (2000); a shape below 1 by
    /// Gamma(shape + 1) U^(1/shape). The rejection loop accepts with probability > 0.95, so
    /// its bound of 1000 tries is never reached in practice; past it the mean is returned.
    pub fn gamma(&mut self, shape: f64) -> f64 {
        if shape < 1.0 {
            let u = self.uniform();
            return self.gamma(shape + 1.0) * u.powf(1.0 / shape);
        }
        let d = shape - 1.0 / 3.0;
        let c = 1.0 / (9.0 * d).sqrt();
        for _ in 0..1000 {
            let x = self.normal();
            let v = (1.0 + c * x).powi(3);
            if v <= 0.0 {
                continue;
            }
            let u = self.uniform();
            if u.ln() < 0.5 * x * x + d - d * v + d * v.ln() {
                return d * v;
            }
        }
        shape
    }

    /// Student-t deviate with `dof` degrees of freedom: Z / sqrt(V / dof), V chi-square(dof)
    /// = 2 Gamma(dof / 2).
    pub fn student_t(&mut self, dof: f64) -> f64 {
        let z = self.normal();
        let v = 2.0 * self.gamma(0.5 * dof);
        z / (v / dof).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Student-t(5) deviates: variance dof / (dof - 2) = 5/3, and P(|T| > 2.571) = 0.05 (the
    /// tabulated two-sided 5% point of t with 5 degrees of freedom).
    #[test]
    fn student_t_deviates_match_the_distribution() {
        let mut r = Rng::new(17);
        let n = 400_000;
        let xs: Vec<f64> = (0..n).map(|_| r.student_t(5.0)).collect();
        let var = xs.iter().map(|x| x * x).sum::<f64>() / n as f64;
        let tail = xs.iter().filter(|x| x.abs() > 2.571).count() as f64 / n as f64;
        // The variance of t(5) converges slowly (infinite fourth moment): 3% is about 4 sd.
        assert!((var - 5.0 / 3.0).abs() < 0.05, "{var}");
        // Binomial sd of the tail fraction: sqrt(0.05 0.95 / n) = 3.4e-4.
        assert!((tail - 0.05).abs() < 0.0015, "{tail}");
    }

    #[test]
    fn normal_deviates_have_unit_variance() {
        let mut r = Rng::new(7);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|_| r.normal()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        // Standard errors: 1/sqrt(n) = 0.0022 for the mean, sqrt(2/n) = 0.0032 for the variance.
        assert!(
            mean.abs() < 0.01 && (var - 1.0).abs() < 0.015,
            "{mean} {var}"
        );
    }
}
