//! `geardyn mesh`: STE and mesh stiffness from the gear geometry (issue 24): waveforms,
//! harmonics and the Harris map as CSV, PNG and SVG, and a JSON summary.

use super::common::{check_out_replaced, print_text};
use super::geometry_excitation::{geometry_error, ReliefArgs};
use super::limits::whole;
use clap::Args as ClapArgs;
use geardyn::data::load_rig_with_geometry;
use geardyn::mesh::{analyse, MeshAnalysis, MeshOptions, ReliefChoice};
use geardyn::plot::{write_panels, write_xy, Marker, Series, XyPlot};
use geardyn::report::Staged;
use std::path::{Path, PathBuf};

#[derive(ClapArgs, Debug)]
#[command(group(clap::ArgGroup::new("relief_depth").required(true)
    .args(["tip_relief_um", "tip_relief_design_load_n"])))]
pub struct Args {
    /// The rig file (rig.toml): [rig] and the optional [geometry] table.
    #[arg(long)]
    rig: PathBuf,
    /// Loads in newtons, each in (0, 1e8]: START:STOP:STEP, or one value.
    #[arg(long = "load-n", allow_hyphen_values = true)]
    load_n: String,
    #[command(flatten)]
    relief: ReliefArgs,
    /// Mesh positions per mesh period, 16 to 16384.
    #[arg(long, default_value_t = 256, allow_hyphen_values = true, value_parser = whole(16..=16_384))]
    samples: usize,
    /// Harmonic orders reported, 1 to 64 (and below half of --samples).
    #[arg(long, default_value_t = 5, allow_hyphen_values = true, value_parser = whole(1..=64))]
    harmonics: usize,
    /// Print the JSON summary on standard output (otherwise a short table).
    #[arg(long)]
    json: bool,
    /// Folder for mesh.json, the CSV files and the figures (replaced as a whole).
    #[arg(long, default_value = "reports/mesh")]
    out: PathBuf,
}

/// START:STOP:STEP or one value, as a list of loads (validated by the library).
fn parse_loads(text: &str) -> anyhow::Result<Vec<f64>> {
    let num = |s: &str, what: &str| -> anyhow::Result<f64> {
        let v: f64 = s.trim().parse().map_err(|_| {
            anyhow::anyhow!(
                "--load-n '{text}': {what} '{s}' is not a number; expected START:STOP:STEP"
            )
        })?;
        if !geardyn::model::valid_load(v) {
            anyhow::bail!(
                "--load-n '{text}': {what} {v} must be in (0, 1e8] N, as every load input of geardyn"
            );
        }
        Ok(v)
    };
    let parts: Vec<&str> = text.split(':').collect();
    match parts.as_slice() {
        [one] => Ok(vec![num(one, "load")?]),
        [a, b, c] => {
            let (start, stop, step) = (num(a, "START")?, num(b, "STOP")?, num(c, "STEP")?);
            if stop < start {
                anyhow::bail!("--load-n '{text}': STOP is below START");
            }
            let n = ((stop - start) / step + 1e-9).floor() as usize + 1;
            if n > 1000 {
                anyhow::bail!("--load-n '{text}': {n} loads; at most 1000");
            }
            Ok((0..n).map(|i| start + i as f64 * step).collect())
        }
        _ => anyhow::bail!("--load-n '{text}': expected START:STOP:STEP, e.g. 945:4725:945"),
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_replaced("--out", &a.out)?;
    let loads = parse_loads(&a.load_n)?;
    let shape = a.relief.shape();
    let relief = match (a.relief.tip_relief_um, a.relief.tip_relief_design_load_n) {
        (Some(amount_um), None) => ReliefChoice::Given {
            amount_um,
            length_mm: a.relief.relief_length_mm,
            shape,
        },
        (None, Some(load_n)) => ReliefChoice::DesignLoad {
            load_n,
            length_mm: a.relief.relief_length_mm,
            shape,
        },
        _ => anyhow::bail!("give one of --tip-relief-um or --tip-relief-design-load-n"),
    };
    let (rig_file, geometry) = load_rig_with_geometry(&a.rig)?;
    let rig = &rig_file.rig;
    // Harris map: 60 loads up to 1.5 x the largest of the loads and the design load.
    let top = 1.5
        * loads
            .iter()
            .copied()
            .chain(a.relief.tip_relief_design_load_n)
            .chain([rig.design_load_n])
            .fold(0.0, f64::max);
    let harris_loads: Vec<f64> = (1..=60).map(|i| top * i as f64 / 60.0).collect();
    let opts = MeshOptions {
        loads_n: loads,
        relief,
        samples: a.samples,
        harmonics: a.harmonics as u32,
        harris_loads_n: harris_loads,
        profile: a.relief.profile()?,
    };
    let r = analyse(rig, &geometry, &opts)
        .map_err(|e| geometry_error(&a.rig, "mesh analysis of", e))?;
    let json = serde_json::to_string_pretty(&r)?;
    let stage = Staged::replacing(&a.out)?;
    stage.write("mesh.json", &format!("{json}\n"))?;
    stage.write("waveforms.csv", &waveforms_csv(&r)?)?;
    stage.write("harmonics.csv", &harmonics_csv(&r)?)?;
    stage.write("harris.csv", &harris_csv(&r)?)?;
    stage.write("pair_stiffness.csv", &pair_csv(&r)?)?;
    write_figures(&r, &rig.name, &stage.path("x"))?;
    let out = stage.commit()?;
    let mut text = if a.json {
        format!("{json}\n")
    } else {
        summary(&r)
    };
    if !a.json {
        text.push_str(&format!(
            "wrote {}/ (mesh.json, CSV, PNG, SVG)\n",
            out.display()
        ));
    } else {
        eprintln!("wrote {}/ (mesh.json, CSV, PNG, SVG)", out.display());
    }
    print_text(&text)
}

/// ", plus a profile table (P + G points)" when one was given.
fn table_text(r: &MeshAnalysis) -> String {
    match r.relief.table_points {
        (0, 0) => String::new(),
        (p, g) => format!(", plus a profile table ({p} pinion + {g} gear points)"),
    }
}

fn summary(r: &MeshAnalysis) -> String {
    let mut s = format!(
        "contact ratio {:.4}, mean mesh stiffness {:.1} N/um with every pair in contact (ISO 6336-1 method B c_gamma_alpha b: {:.1} N/um; with the typical c' = 14: {:.1} N/um, the k_h that sweep and validate use when rig.toml gives none)\n\
         tip relief {:.2} um over {:.2} mm ({}){}{}\n",
        r.contact_ratio,
        r.mesh_stiffness_mean_n_per_um,
        r.iso6336_mesh_stiffness_n_per_um,
        r.iso6336_typical_mesh_stiffness_n_per_um,
        r.relief.amount_um,
        r.relief.length_mm,
        r.relief.shape.name(),
        r.relief
            .designed_for_load_n
            .map_or(String::new(), |l| format!(
                ", sized for minimum STE pp at {l} N"
            )),
        table_text(r)
    );
    // f_ah1 is the STE's own first harmonic over b; `--excitation geometry` with k(t) excites
    // the model by the STE less its own deflection, whose first harmonic is larger.
    s.push_str("  load_n  ste_pp_um  ste_e1_um  f_ah1 (e1/b)  k_mean_n_per_um  contact_loss\n");
    for l in &r.loads {
        s.push_str(&format!(
            "{:>8.1}  {:>9.3}  {:>9.3}  {:>12.4}  {:>15.1}  {:>11.1}%\n",
            l.load_n,
            l.ste_pp_um,
            l.harmonics.first().map_or(0.0, |h| h.ste_amplitude_um),
            l.f_ah1,
            l.mesh_stiffness_mean_n_per_um,
            100.0 * l.contact_loss_fraction
        ));
    }
    s
}

fn csv_text(header: &[&str], rows: Vec<Vec<String>>) -> anyhow::Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header)?;
    for r in rows {
        w.write_record(r)?;
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}

fn waveforms_csv(r: &MeshAnalysis) -> anyhow::Result<String> {
    let mut rows = Vec::new();
    for l in &r.loads {
        let w = &l.waveform;
        for i in 0..w.position.len() {
            let pair = |j: usize| {
                w.pairs[i]
                    .get(j)
                    .map_or(String::new(), |p| format!("{:.6}", p.load_n))
            };
            rows.push(vec![
                format!("{}", l.load_n),
                format!("{:.6}", w.position[i]),
                format!("{:.6}", w.ste_um[i]),
                format!("{:.6}", w.stiffness_n_per_um[i]),
                format!("{:.6}", w.geometric_stiffness_n_per_um[i]),
                format!("{:.6}", r.relief_profile_um[i]),
                pair(0),
                pair(1),
                pair(2),
            ]);
        }
    }
    csv_text(
        &[
            "load_n",
            "mesh_position",
            "ste_um",
            "mesh_stiffness_n_per_um",
            "mesh_stiffness_no_relief_n_per_um",
            "relief_profile_um",
            "pair1_load_n",
            "pair2_load_n",
            "pair3_load_n",
        ],
        rows,
    )
}

fn harmonics_csv(r: &MeshAnalysis) -> anyhow::Result<String> {
    let rows = r
        .loads
        .iter()
        .flat_map(|l| {
            l.harmonics.iter().map(move |h| {
                vec![
                    format!("{}", l.load_n),
                    h.order.to_string(),
                    format!("{:.6}", h.ste_amplitude_um),
                    format!("{:.6}", h.ste_phase_rad),
                    format!("{:.6}", h.stiffness_eps),
                    format!("{:.6}", h.stiffness_phase_rad),
                ]
            })
        })
        .collect();
    csv_text(
        &[
            "load_n",
            "order",
            "ste_amplitude_um",
            "ste_phase_rad",
            "stiffness_eps",
            "stiffness_phase_rad",
        ],
        rows,
    )
}

fn harris_csv(r: &MeshAnalysis) -> anyhow::Result<String> {
    let rows = r
        .harris
        .iter()
        .map(|p| vec![format!("{:.3}", p.load_n), format!("{:.6}", p.ste_pp_um)])
        .collect();
    csv_text(&["load_n", "ste_pp_um"], rows)
}

fn pair_csv(r: &MeshAnalysis) -> anyhow::Result<String> {
    let rows = r
        .pair_stiffness
        .iter()
        .map(|(s, k)| vec![format!("{s:.6}"), format!("{k:.6}")])
        .collect();
    csv_text(&["roll_mm", "pair_stiffness_n_per_um"], rows)
}

/// ste.{png,svg} (STE and loaded stiffness over a mesh period), harris.{png,svg},
/// pair_stiffness.{png,svg}, in the folder of `stem`.
fn write_figures(r: &MeshAnalysis, rig_name: &str, stem: &Path) -> anyhow::Result<()> {
    let dir = stem.parent().unwrap_or(Path::new("."));
    let relief = format!(
        "tip relief {:.1} µm over {:.2} mm ({}){}{}",
        r.relief.amount_um,
        r.relief.length_mm,
        r.relief.shape.name(),
        r.relief
            .designed_for_load_n
            .map_or(String::new(), |l| format!(", sized for {l:.0} N")),
        table_text(r)
    );
    let x_label = "mesh position τ (fraction of the base pitch)";
    let mut ste = XyPlot::new("Loaded static transmission error", x_label, "STE δ (µm)")
        .with_caption(relief.clone());
    let mut k = XyPlot::new("Loaded mesh stiffness", x_label, "k (N/µm)").with_caption(format!(
        "transverse contact ratio {:.3}; jumps where a pair enters, leaves or loses contact",
        r.contact_ratio
    ));
    for (i, l) in r.loads.iter().enumerate() {
        let w = &l.waveform;
        let pts = |v: &[f64]| w.position.iter().copied().zip(v.iter().copied()).collect();
        let label = format!("{:.0} N", l.load_n);
        ste.series
            .push(Series::line(label.clone(), pts(&w.ste_um)).with_color(i));
        k.series
            .push(Series::line(label, pts(&w.stiffness_n_per_um)).with_color(i));
    }
    // Head room above the curves keeps the legend (placed in the emptiest corner) off the data.
    for p in [&mut ste, &mut k] {
        let (lo, hi) = p
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|q| q.1))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
                (a.min(y), b.max(y))
            });
        if lo.is_finite() && hi > lo {
            let span = hi - lo;
            p.y_range = Some((lo - 0.05 * span, hi + 0.45 * span));
        }
    }
    write_panels(rig_name, &[ste, k], 2, &dir.join("ste"))?;
    let mut harris = XyPlot::new("Harris map", "load F (N)", "STE peak-to-peak (µm)")
        .with_caption(relief)
        .with_series(Series::line(
            "STE pp",
            r.harris.iter().map(|p| (p.load_n, p.ste_pp_um)).collect(),
        ))
        .with_series(
            Series::markers(
                "requested loads",
                r.loads.iter().map(|l| (l.load_n, l.ste_pp_um)).collect(),
            )
            .with_marker(Marker::Square),
        );
    harris.y_range = Some((
        0.0,
        1.08 * r.harris.iter().map(|p| p.ste_pp_um).fold(0.0, f64::max),
    ));
    if let Some(l) = r.relief.designed_for_load_n {
        harris = harris.with_vline(l, "design load");
    }
    write_xy(&harris, &dir.join("harris"))?;
    let g = &r.geometry;
    let pair = XyPlot::new(
        "Tooth-pair stiffness along the path of contact",
        "roll distance from T₁ (mm)",
        "pair stiffness k (N/µm)",
    )
    .with_caption(format!(
        "potential energy (bending, shear, axial, Hertz, Sainsot foundation); E = {:.0} GPa, ν = {}; shaded: single-tooth contact",
        g.youngs_modulus_gpa, g.poisson_ratio
    ))
    .with_series(Series::line("one pair", r.pair_stiffness.clone()))
    .with_band(g.single_contact_from_mm, g.single_contact_to_mm)
    .with_vline(g.pitch_point_mm, "pitch point");
    let mut pair = pair;
    pair.legend = false;
    write_xy(&pair, &dir.join("pair_stiffness"))?;
    Ok(())
}
