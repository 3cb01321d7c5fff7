use geardyn::model::{Dimensional, GearPair, Term};
use geardyn::sim::*;
use geardyn::validate::munro_rig;
use std::time::Instant;
fn main() {
    let dim = Dimensional::from_rig(&munro_rig()).unwrap();
    let speeds: Vec<f64> = (0..81).map(|i| 1000.0 + 50.0 * i as f64).collect();
    for (load, ste) in [(3780.0, 0.3), (945.0, 3.5)] {
        for rtol in [0.0, 1e-9, 1e-7, 1e-6, 1e-5] {
            let mut m =
                GearPair::paper(dim.mean_force(load), dim.ste_amplitude(ste), 0.0175, 1.0).unwrap();
            if rtol > 0.0 {
                m.stiffness = vec![Term {
                    order: 1,
                    amplitude: 0.0,
                    phase: 0.0,
                }];
            }
            let m = m.validated().unwrap();
            let f = move |g: &GearPair| -> geardyn::error::Result<Box<dyn PeriodFlow>> {
                if rtol > 0.0 {
                    Ok(Box::new(RkFlow::new(g, rtol)?))
                } else {
                    Ok(Box::new(ExactFlow::new(g)?))
                }
            };
            let omegas: Vec<f64> = speeds.iter().map(|&s| dim.omega(s, 1600.0)).collect();
            let plan = SweepPlan {
                omegas,
                branch: Branch::Up,
                x0: [1.0 + m.mean_force, 0.0],
                grid: IcGrid::new(-2.0, 2.0, 1).unwrap(),
                opts: SteadyOptions::default(),
            };
            let t = Instant::now();
            let pts = sweep(&f, &m, &plan, &geardyn::progress::NoProgress).unwrap();
            let v: Vec<f64> = pts.iter().map(|p| dim.dte_um(p.steady.dte_pp)).collect();
            println!(
                "load {load} rtol {rtol:e}: {:?} ms, sum {:.6} v40 {:.5}",
                t.elapsed().as_millis(),
                v.iter().sum::<f64>(),
                v[40]
            );
        }
    }
}
