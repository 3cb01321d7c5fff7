//! Sec. 3 (digital simulation, Figs 2-9): coexisting attractors at the paper's frequencies, basin
//! maps, chaos, the load and damping sequences of Figs 7 and 8, and their claim rows.

use super::artifacts::Artifact;
use super::attractor_set::{
    confirmed, describe, describe_all, dominant, impact_name, match_expected, motion_name, name,
    search, Expected, Horizon, Point,
};
use super::claims::{agree_if, Claim, ReportTable, Verdict};
use super::sec3_transients::{chaos_claim, chaos_range_claim, sets_table, window_omegas};
use super::steady_figures::{orbit_samples, periods_to_draw, steady_figures};
use super::Resolution;
use crate::error::Result;
use crate::model::Impact;
use crate::plot::{CategoryMap, Series, XyPlot};
use crate::progress::Progress;
use crate::sim::{AttractorMap, ExactFlow, IcGrid, Motion, SetKind};
use rayon::prelude::*;

/// Output sub-folder of the Sec. 3 figures.
pub const DIR: &str = "sec3-simulation";

const FM: f64 = 0.1;
const ZETA: f64 = 0.02;
/// F_hat = 0.5 (lightly loaded, Figs 2-4).
const FAH_LIGHT: f64 = 0.2;
/// F_hat = 2 (heavily loaded, Figs 5-6).
const FAH_HEAVY: f64 = 0.05;
/// The frequencies of Figs 2 and 5.
const FIG2_OMEGAS: [f64; 6] = [0.3, 0.5, 0.6, 0.7, 0.8, 1.0];

/// Every attractor search of Sec. 3 (and the damping maps of Fig. 14 used in Sec. 5).
pub(crate) struct Searches {
    pub(crate) points: Vec<(Point, IcGrid)>,
    /// Non-periodic sets followed to their escape (the default search).
    pub(crate) maps: Vec<AttractorMap>,
    /// The same searches at the paper's time scale (no following), for the claim grid only.
    pub(crate) paper: Vec<Option<AttractorMap>>,
}

impl Searches {
    fn index(&self, p: Point, grid: &IcGrid) -> Option<usize> {
        self.points.iter().position(|(q, g)| *q == p && g == grid)
    }

    /// The map computed for `p` on `grid`.
    pub(crate) fn get(&self, p: Point, grid: &IcGrid) -> Option<&AttractorMap> {
        self.index(p, grid).map(|i| &self.maps[i])
    }

    /// The map of `p` on `grid` at the paper's time scale, when computed.
    pub(crate) fn get_paper(&self, p: Point, grid: &IcGrid) -> Option<&AttractorMap> {
        self.index(p, grid).and_then(|i| self.paper[i].as_ref())
    }
}

/// One of the paper's parameter sets at a frequency (or other swept value).
type PointAt = fn(f64) -> Point;

pub(crate) fn light(omega: f64) -> Point {
    Point {
        fm: FM,
        fah: FAH_LIGHT,
        zeta: ZETA,
        omega,
    }
}

fn heavy(omega: f64) -> Point {
    Point {
        fm: FM,
        fah: FAH_HEAVY,
        zeta: ZETA,
        omega,
    }
}

fn fig7(fm: f64) -> Point {
    Point {
        fm,
        fah: FAH_LIGHT,
        zeta: ZETA,
        omega: 1.0,
    }
}

fn fig8(zeta: f64) -> Point {
    Point {
        fm: FM,
        fah: FAH_LIGHT,
        zeta,
        omega: 1.0,
    }
}

/// Fig. 14: case III domains at Omega 0.5, F_hat 0.5, for zeta 0.02, 0.03, 0.04.
pub(crate) fn fig14(zeta: f64) -> Point {
    Point {
        fm: FM,
        fah: FAH_LIGHT,
        zeta,
        omega: 0.5,
    }
}

const LIGHT_OMEGAS: [f64; 8] = [0.3, 0.5, 0.6, 0.7, 0.8, 1.0, 1.25, 1.5];
const HEAVY_OMEGAS: [f64; 9] = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.2, 1.5];
const FIG7_FM: [f64; 4] = [0.1, 0.15, 0.2, 0.3];
const FIG8_ZETA: [f64; 2] = [0.05, 0.1];
const FIG14_ZETA: [f64; 3] = [0.02, 0.03, 0.04];

/// The searches of the claims (paper's IC grid) and of the basin maps (finer grid).
pub(crate) fn plan(res: &Resolution) -> Result<Vec<(Point, IcGrid)>> {
    let g = IcGrid::new(-2.0, 2.0, res.ic_n)?;
    let b = IcGrid::new(-2.0, 2.0, res.basin_n)?;
    let mut v: Vec<(Point, IcGrid)> = Vec::new();
    v.extend(LIGHT_OMEGAS.iter().map(|&w| (light(w), g)));
    v.extend(HEAVY_OMEGAS.iter().map(|&w| (heavy(w), g)));
    v.extend(FIG7_FM[1..].iter().map(|&f| (fig7(f), g)));
    v.extend(FIG8_ZETA.iter().map(|&z| (fig8(z), g)));
    v.extend(FIG14_ZETA.iter().map(|&z| (fig14(z), b)));
    v.push((heavy(0.6), b));
    Ok(v)
}

/// Run every search in parallel (order of `plan` kept); the claim-grid points also at the
/// paper's time scale.
pub(crate) fn run_searches(res: &Resolution, progress: &dyn Progress) -> Result<Searches> {
    let points = plan(res)?;
    let claim_grid = IcGrid::new(-2.0, 2.0, res.ic_n)?;
    let maps: Vec<Result<(AttractorMap, Option<AttractorMap>)>> = points
        .par_iter()
        .map(|(p, g)| {
            let followed = search(p, g, false, Horizon::Followed)?;
            let paper = if *g == claim_grid {
                Some(search(p, g, false, Horizon::Paper)?)
            } else {
                None
            };
            progress.advance(1);
            Ok((followed, paper))
        })
        .collect();
    let (maps, paper) = maps
        .into_iter()
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .unzip();
    Ok(Searches {
        points,
        maps,
        paper,
    })
}

/// One claim about the attractor list at a point.
struct Spec {
    id: &'static str,
    figure: &'static str,
    paper: &'static str,
    point: Point,
    expected: Vec<Expected>,
    /// The paper's attractor must also have the largest basin.
    dominant: bool,
}

fn p(period: u32) -> Expected {
    Expected {
        period: Some(period),
        impact: None,
    }
}

fn pi(period: u32, impact: Impact) -> Expected {
    Expected {
        period: Some(period),
        impact: Some(impact),
    }
}

fn specs() -> Vec<Spec> {
    vec![
        Spec {
            id: "S3-01",
            figure: "Fig. 2(a)",
            paper: "F_hat 0.5, zeta 0.02, Omega_h 0.3: all transients converge to one period-1 attractor",
            point: light(0.3),
            expected: vec![p(1)],
            dominant: false,
        },
        Spec {
            id: "S3-02",
            figure: "Fig. 2(b), 3",
            paper: "Omega_h 0.5: three coexisting period-1 attractors (no, single-sided, double-sided impact)",
            point: light(0.5),
            expected: vec![
                pi(1, Impact::None),
                pi(1, Impact::Single),
                pi(1, Impact::Double),
            ],
            dominant: false,
        },
        Spec {
            id: "S3-03",
            figure: "Fig. 2(c)",
            paper: "Omega_h 0.6: two period-1 attractors",
            point: light(0.6),
            expected: vec![p(1), p(1)],
            dominant: false,
        },
        Spec {
            id: "S3-04",
            figure: "Fig. 2(d)",
            paper: "Omega_h 0.7: two period-1 and two period-3 attractors",
            point: light(0.7),
            expected: vec![p(1), p(1), p(3), p(3)],
            dominant: false,
        },
        Spec {
            id: "S3-05",
            figure: "Fig. 2(e)",
            paper: "Omega_h 0.8: only a period-2 attractor",
            point: light(0.8),
            expected: vec![p(2)],
            dominant: true,
        },
        Spec {
            id: "S3-11a",
            figure: "Fig. 5(f)",
            paper: "F_hat 2, Omega_h 1.0: one period-2 attractor coexists with the period-1 orbit",
            point: heavy(1.0),
            expected: vec![p(1), p(2)],
            dominant: false,
        },
        Spec {
            id: "S3-11b",
            figure: "Sec. 3 text",
            paper: "F_hat 2, Omega_h 1.2: one period-2 attractor coexists with the period-1 orbit",
            point: heavy(1.2),
            expected: vec![p(1), p(2)],
            dominant: false,
        },
        Spec {
            id: "S3-11c",
            figure: "Sec. 3 text",
            paper: "F_hat 2, Omega_h 1.5: one period-2 attractor coexists with the period-1 orbit",
            point: heavy(1.5),
            expected: vec![p(1), p(2)],
            dominant: false,
        },
        Spec {
            id: "S3-14",
            figure: "Fig. 8(a)",
            paper: "F_hat 0.5, Omega_h 1.0 (Fig. 4's): zeta 0.05 reduces chaos to a period-8 attractor",
            point: fig8(0.05),
            expected: vec![p(8)],
            dominant: false,
        },
        Spec {
            id: "S3-15",
            figure: "Fig. 8(b)",
            paper: "zeta 0.1: the period-8 attractor bifurcates to a period-2 orbit",
            point: fig8(0.1),
            expected: vec![p(2)],
            dominant: true,
        },
    ]
}

/// Sec. 3 claims and figures. `searches` holds the exact maps; points whose extra attractors need
/// confirmation are searched again with DOP853 here.
/// What Sec. 3 contributes: claims, figures, the DOP853 confirmations (used by Sec. 5) and the
/// evidence tables.
pub(crate) type Sec3Outputs = (Vec<Claim>, Vec<Artifact>, Confirmations, Vec<ReportTable>);

pub(crate) fn build(
    res: &Resolution,
    searches: &Searches,
    progress: &dyn Progress,
) -> Result<Sec3Outputs> {
    let found = Found {
        searches,
        ic: IcGrid::new(-2.0, 2.0, res.ic_n)?,
        basin: IcGrid::new(-2.0, 2.0, res.basin_n)?,
    };
    let specs = specs();
    let confirmations = confirm(&found, &specs)?;
    progress.advance(1);
    let scan = window_scan(&found.ic, res.window_step)?;
    progress.advance(1);
    let (claims, table) = claims_and_table(&found, &specs, &confirmations, &scan)?;
    let figs = figures(&found)?;
    Ok((claims, figs, confirmations, vec![table]))
}

/// S3-07's scan of Fig. 4's parameters over 1.0 <= Omega <= 1.5, the non-periodic sets
/// followed to their escape.
fn window_scan(grid: &IcGrid, step: f64) -> Result<Vec<(f64, AttractorMap)>> {
    window_omegas(step)
        .par_iter()
        .map(|&w| Ok((w, search(&light(w), grid, false, Horizon::Followed)?)))
        .collect()
}

/// Which initial-condition grid a search covered.
#[derive(Clone, Copy)]
enum Grid {
    /// The attractor search's grid.
    Ic,
    /// The basin maps' finer grid.
    Basin,
}

/// The searches of Sec. 3's points on their grids.
struct Found<'a> {
    searches: &'a Searches,
    ic: IcGrid,
    basin: IcGrid,
}

impl Found<'_> {
    fn grid(&self, grid: Grid) -> &IcGrid {
        match grid {
            Grid::Ic => &self.ic,
            Grid::Basin => &self.basin,
        }
    }

    /// The search at `pt` on `grid`.
    fn get(&self, pt: Point, grid: Grid) -> Result<&AttractorMap> {
        self.searches
            .get(pt, self.grid(grid))
            .ok_or_else(|| missing(pt))
    }

    /// The paper's and the exact flow's searches at `pt` on the attractor grid.
    fn both(&self, pt: Point) -> Result<(&AttractorMap, &AttractorMap)> {
        let paper = self
            .searches
            .get_paper(pt, &self.ic)
            .ok_or_else(|| missing(pt))?;
        Ok((paper, self.get(pt, Grid::Ic)?))
    }
}

fn missing(pt: Point) -> crate::error::GearError {
    crate::error::GearError::Numerical(format!("internal: no search at {}", pt.caption()))
}

/// The points with attractors beyond the paper's list (and the light-load points with more than
/// one), searched again with DOP853.
fn confirm(found: &Found, specs: &[Spec]) -> Result<Confirmations> {
    let mut to_confirm: Vec<Point> = Vec::new();
    for s in specs {
        let m = found.get(s.point, Grid::Ic)?;
        if !match_expected(m, &s.expected).extra.is_empty() && !to_confirm.contains(&s.point) {
            to_confirm.push(s.point);
        }
    }
    for w in [1.0, 1.25, 1.5] {
        let m = found.get(light(w), Grid::Ic)?;
        if m.attractors.len() > 1 && !to_confirm.contains(&light(w)) {
            to_confirm.push(light(w));
        }
    }
    let rk: Vec<Result<AttractorMap>> = to_confirm
        .par_iter()
        .map(|pt| search(pt, &found.ic, true, Horizon::Followed))
        .collect();
    let rk: Vec<AttractorMap> = rk.into_iter().collect::<Result<_>>()?;
    Ok(Confirmations {
        points: to_confirm,
        maps: rk,
    })
}

/// Sec. 3's claim rows, sorted by id, and the evidence table of every point's attractors.
fn claims_and_table(
    found: &Found,
    specs: &[Spec],
    confirmations: &Confirmations,
    scan: &[(f64, AttractorMap)],
) -> Result<(Vec<Claim>, ReportTable)> {
    let mut claims = Vec::new();
    for s in specs {
        let m = found.get(s.point, Grid::Ic)?;
        claims.push(list_claim(s, m, confirmations));
    }
    claims.push(chaos_claim(found.both(light(1.0))?, confirmations));
    claims.push(chaos_range_claim(
        &[1.0, 1.25, 1.5]
            .iter()
            .map(|&w| found.both(light(w)).map(|m| (w, m)))
            .collect::<Result<Vec<_>>>()?,
        scan,
    ));
    claims.push(heavy_period_one_claim(
        &HEAVY_OMEGAS[..6]
            .iter()
            .map(|&w| found.get(heavy(w), Grid::Ic).map(|m| (w, m)))
            .collect::<Result<Vec<_>>>()?,
    ));
    claims.push(heavy_no_chaos_claim(
        &HEAVY_OMEGAS
            .iter()
            .map(|&w| found.get(heavy(w), Grid::Ic).map(|m| (w, m)))
            .collect::<Result<Vec<_>>>()?,
    ));
    claims.push(basin_claim(
        "S3-08",
        "Fig. 3",
        "Omega_h 0.5, F_hat 0.5: domains of attraction of three attractors (no, single-sided, double-sided impact) in -2 < q(0), q'(0) < 2",
        found.get(fig14(0.02), Grid::Basin)?,
        &[Impact::None, Impact::Single, Impact::Double],
    ));
    claims.push(basin_claim(
        "S3-12",
        "Fig. 6",
        "F_hat 2, Omega_h 0.6: domains of attraction of two attractors (no impact, single-sided impact)",
        found.get(heavy(0.6), Grid::Basin)?,
        &[Impact::None, Impact::Single],
    ));
    claims.push(fig7_claim(
        &FIG7_FM
            .iter()
            .map(|&f| {
                let pt = if f == FM { light(1.0) } else { fig7(f) };
                found.both(pt).map(|m| (f / FAH_LIGHT, m))
            })
            .collect::<Result<Vec<_>>>()?,
    ));
    let mut table_points: Vec<Point> = LIGHT_OMEGAS.iter().map(|&w| light(w)).collect();
    table_points.extend(HEAVY_OMEGAS.iter().map(|&w| heavy(w)));
    table_points.extend(FIG7_FM[1..].iter().map(|&f| fig7(f)));
    table_points.extend(FIG8_ZETA.iter().map(|&z| fig8(z)));
    let table = sets_table(
        &table_points
            .iter()
            .map(|&pt| found.both(pt).map(|(a, b)| (pt, a, b)))
            .collect::<Result<Vec<_>>>()?,
        confirmations,
    );
    claims.sort_by(|a, b| a.id.cmp(&b.id));

    Ok((claims, table))
}

/// Figs 2-9.
fn figures(found: &Found) -> Result<Vec<Artifact>> {
    let mut figs = Vec::new();
    let planes: [(&str, &str, PointAt); 2] = [
        (
            "fig02-phase-planes",
            "Fig. 2: phase planes, F_hat = 0.5",
            light,
        ),
        (
            "fig05-phase-planes",
            "Fig. 5: phase planes, F_hat = 2",
            heavy,
        ),
    ];
    for (name, title, point) in planes {
        figs.push(phase_planes(
            name,
            title,
            &FIG2_OMEGAS
                .iter()
                .map(|&w| found.get(point(w), Grid::Ic).map(|m| (point(w), m)))
                .collect::<Result<Vec<_>>>()?,
        )?);
    }
    figs.push(basin_map(
        DIR,
        "fig03-basins",
        "Fig. 3: domains of attraction",
        fig14(0.02),
        found.get(fig14(0.02), Grid::Basin)?,
    ));
    figs.push(basin_map(
        DIR,
        "fig06-basins",
        "Fig. 6: domains of attraction",
        heavy(0.6),
        found.get(heavy(0.6), Grid::Basin)?,
    ));
    figs.push(chaos_figure(light(1.0), found.get(light(1.0), Grid::Ic)?)?);
    figs.push(histories(
        "fig07-time-histories",
        "Fig. 7: time histories (chaotic set, else dominant attractor), F_ah = 0.2, ζ = 0.02, Ω = 1.0",
        &FIG7_FM
            .iter()
            .map(|&f| {
                let pt = if f == FM { light(1.0) } else { fig7(f) };
                found.get(pt, Grid::Ic).map(|m| (pt, m, None))
            })
            .collect::<Result<Vec<_>>>()?,
    )?);
    figs.push(histories(
        "fig08-time-histories",
        "Fig. 8: time histories, F_m = 0.1, F_hat = 0.5, Omega_h = 1.0",
        &FIG8_ZETA
            .iter()
            .map(|&z| {
                found
                    .get(fig8(z), Grid::Ic)
                    .map(|m| (fig8(z), m, Some(if z == 0.05 { 8 } else { 2 })))
            })
            .collect::<Result<Vec<_>>>()?,
    )?);
    figs.push(impact_regimes(
        light(0.5),
        found.get(light(0.5), Grid::Ic)?,
    )?);
    Ok(figs)
}

/// DOP853 re-searches of the points where the exact flow found more than the paper.
pub(crate) struct Confirmations {
    pub(crate) points: Vec<Point>,
    pub(crate) maps: Vec<AttractorMap>,
}

impl Confirmations {
    pub(crate) fn get(&self, p: Point) -> Option<&AttractorMap> {
        self.points
            .iter()
            .position(|q| *q == p)
            .map(|i| &self.maps[i])
    }
}

fn list_claim(s: &Spec, m: &AttractorMap, conf: &Confirmations) -> Claim {
    let mt = match_expected(m, &s.expected);
    let found = describe_all(m);
    let dom = dominant(m);
    let dom_ok = !s.dominant
        || dom.is_some_and(|d| d.steady.period == s.expected.first().and_then(|e| e.period));
    let (verdict, expl) = if !mt.missing.is_empty() || !dom_ok {
        (
            Verdict::Differ,
            if dom_ok {
                format!(
                    "{} of the paper's {} attractor(s) not found on the {}x{} grid",
                    mt.missing.len(),
                    s.expected.len(),
                    m.grid.n,
                    m.grid.n
                )
            } else {
                format!(
                    "the largest basin belongs to {}, not to the paper's attractor",
                    dom.map_or("nothing".into(), describe)
                )
            },
        )
    } else if mt.extra.is_empty() {
        (
            Verdict::Agree,
            format!(
                "exactly the paper's {} attractor(s) on the {}x{} grid",
                s.expected.len(),
                m.grid.n,
                m.grid.n
            ),
        )
    } else {
        extra_verdict(s.point, m, &mt.extra, conf)
    };
    Claim::new(s.id, "3", s.figure, s.paper, found, verdict, expl)
}

/// Verdict for attractors beyond the paper's list: "more than the paper" for those DOP853 finds
/// too; the others are named but not counted.
pub(crate) fn extra_verdict(
    pt: Point,
    m: &AttractorMap,
    extra: &[usize],
    conf: &Confirmations,
) -> (Verdict, String) {
    let (yes, no): (Vec<usize>, Vec<usize>) = extra
        .iter()
        .partition(|&&i| conf.get(pt).is_some_and(|rk| confirmed(m, i, rk)));
    let names = |v: &[usize]| {
        v.iter()
            .map(|&i| describe(&m.attractors[i]))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let unconfirmed = if no.is_empty() {
        String::new()
    } else {
        format!(
            "; {} further one(s) found by the exact flow only (not confirmed by DOP853, not counted): {}",
            no.len(),
            names(&no)
        )
    };
    if yes.is_empty() {
        (
            Verdict::Agree,
            format!("the paper's attractor(s) found{unconfirmed}"),
        )
    } else {
        (
            Verdict::MoreThanPaper,
            format!(
                "the paper's attractor(s) plus {} more, found by both integrators (exact and DOP853 rtol 1e-11; periodic orbits with q_a within 1e-6): {}{unconfirmed}",
                yes.len(),
                names(&yes)
            ),
        )
    }
}

fn heavy_period_one_claim(maps: &[(f64, &AttractorMap)]) -> Claim {
    let bad: Vec<String> = maps
        .iter()
        .filter(|(_, m)| m.attractors.iter().any(|a| a.steady.period != Some(1)))
        .map(|(w, m)| format!("Omega {w}: {}", describe_all(m)))
        .collect();
    let counts: Vec<String> = maps
        .iter()
        .map(|(w, m)| format!("{w}: {}", m.attractors.len()))
        .collect();
    Claim::new(
        "S3-09",
        "3",
        "Fig. 5(a)-(e)",
        "F_hat 2, zeta 0.02: all solutions are period-1 for Omega_h < 1.0",
        format!(
            "period-1 attractors per Omega: {}{}",
            counts.join(", "),
            if bad.is_empty() {
                String::new()
            } else {
                format!("; not period-1: {}", bad.join("; "))
            }
        ),
        agree_if(bad.is_empty()),
        if bad.is_empty() {
            format!(
                "every attractor at the {} frequencies is period-1",
                maps.len()
            )
        } else {
            format!("{} frequencies have other attractors", bad.len())
        },
    )
}

fn heavy_no_chaos_claim(maps: &[(f64, &AttractorMap)]) -> Claim {
    let chaotic: Vec<f64> = maps
        .iter()
        .filter(|(_, m)| m.attractors.iter().any(|a| a.steady.period.is_none()))
        .map(|(w, _)| *w)
        .collect();
    Claim::new(
        "S3-10",
        "3",
        "Fig. 5",
        "F_hat 2, zeta 0.02: unlike F_hat 0.5, no chaotic responses",
        format!(
            "non-periodic attractors at {} of {} frequencies (0.3-1.5){}",
            chaotic.len(),
            maps.len(),
            if chaotic.is_empty() {
                String::new()
            } else {
                format!(": Omega {chaotic:?}")
            }
        ),
        agree_if(chaotic.is_empty()),
        if chaotic.is_empty() {
            "every attractor found is periodic".into()
        } else {
            "non-periodic attractors exist".into()
        },
    )
}

fn basin_claim(id: &str, fig: &str, paper: &str, m: &AttractorMap, impacts: &[Impact]) -> Claim {
    let kinds: Vec<Impact> = m
        .attractors
        .iter()
        .filter(|a| a.steady.period == Some(1))
        .map(|a| a.steady.impact)
        .collect();
    let ok = m.attractors.len() == impacts.len() && impacts.iter().all(|i| kinds.contains(i));
    let extra = m.attractors.len().saturating_sub(impacts.len());
    Claim::new(
        id,
        "3",
        fig,
        paper,
        format!("{}x{} map: {}", m.grid.n, m.grid.n, describe_all(m)),
        agree_if(ok),
        if ok {
            format!(
                "the {} period-1 domains of the paper, with their impact regimes",
                impacts.len()
            )
        } else {
            format!(
                "{} attractor(s) on the map where the paper shows {}{}",
                m.attractors.len(),
                impacts.len(),
                if extra > 0 {
                    " (small extra domains at this resolution)"
                } else {
                    ""
                }
            )
        },
    )
}

/// Fig. 7's sequence from the dominant set at the paper's time scale; a dominant set that is a
/// chaotic transient when followed is named as such.
fn fig7_claim(maps: &[(f64, (&AttractorMap, &AttractorMap))]) -> Claim {
    let dom: Vec<(f64, String, bool)> = maps
        .iter()
        .map(|(fh, (paper, followed))| {
            let transient = followed
                .attractors
                .iter()
                .any(|a| a.kind == SetKind::ChaoticTransient);
            (
                *fh,
                dominant(paper).map_or("nothing".into(), motion_name),
                transient,
            )
        })
        .collect();
    let at = |fh: f64| {
        dom.iter()
            .find(|(f, _, _)| (f - fh).abs() < 1e-9)
            .map(|(_, k, _)| k.clone())
            .unwrap_or_default()
    };
    let paper_ok = at(0.75) == "chaotic" && at(1.0) == "period-2" && at(1.5) == "period-1";
    let shifted = at(0.5) == "chaotic" && at(0.75) == "period-2" && at(1.0) == "period-1";
    let text: Vec<String> = dom
        .iter()
        .map(|(f, k, t)| {
            format!(
                "F_hat {f:.2}: {k}{}",
                if *t {
                    " (a chaotic transient when followed)"
                } else {
                    ""
                }
            )
        })
        .collect();
    Claim::new(
        "S3-13",
        "3",
        "Fig. 7",
        "F_ah 0.2, zeta 0.02: chaos, then period-2, then period-1 as F_hat goes 0.75, 1.0, 1.5 (Omega_h not stated; geardyn uses Fig. 4's 1.0)",
        format!(
            "dominant set at Omega_h 1.0 after the default transient (the paper's time scale): {}",
            text.join(", ")
        ),
        agree_if(paper_ok),
        if paper_ok {
            "the paper's sequence at the paper's force ratios".into()
        } else if shifted {
            "the same sequence chaos, period-2, period-1, shifted to lower F_hat (0.5, 0.75, 1.0); the chaos at F_hat 0.5 is itself a transient (row S3-06)".into()
        } else {
            "a different sequence of dominant attractors".into()
        },
    )
}

fn flow_of(pt: &Point) -> Result<ExactFlow> {
    ExactFlow::new(&pt.model()?)
}

/// One phase-plane panel per frequency, one closed orbit (or 40 periods) per attractor.
fn phase_planes(stem: &str, title: &str, maps: &[(Point, &AttractorMap)]) -> Result<Artifact> {
    let mut panels = Vec::new();
    for (pt, m) in maps {
        let flow = flow_of(pt)?;
        let mut series = Vec::new();
        for a in &m.attractors {
            // One closed orbit, or 12 forcing periods of non-periodic motion.
            let n = a.steady.period.map_or(12, |p| p as usize);
            let s = orbit_samples(&flow, &a.steady, n)?;
            let label = format!("{} {:.1}%", name(a), 100.0 * a.basin_fraction);
            let pts: Vec<(f64, f64)> = s.iter().map(|x| (x.q, x.v)).collect();
            // The colour is the impact regime in every panel (case I, II, III as in the
            // response figures); a subharmonic is dashed, non-periodic motion dotted.
            let colour = usize::from(a.steady.impact.case() - 1);
            series.push(match a.steady.period {
                None => Series::markers(label, pts)
                    .with_color(colour)
                    .with_marker(crate::plot::Marker::Dot),
                Some(1) => Series::line(label, pts).with_color(colour),
                Some(_) => Series::dashed(label, pts).with_color(colour),
            });
        }
        panels.push(XyPlot {
            title: format!("Omega_h = {}", pt.omega),
            caption: Some(format!("{}, {}x{} ICs", pt.caption(), m.grid.n, m.grid.n)),
            x_label: "q (dimensionless)".into(),
            y_label: "q' (dimensionless)".into(),
            series,
            ..XyPlot::default()
        });
    }
    Ok(Artifact::Panels {
        dir: DIR.into(),
        stem: stem.into(),
        title: format!("{title} (colour: impact regime; dashed: subharmonic)"),
        panels,
        cols: 3,
    })
}

/// A basin map with one legend entry per attractor.
pub(crate) fn basin_map(
    dir: &str,
    stem: &str,
    title: &str,
    pt: Point,
    m: &AttractorMap,
) -> Artifact {
    let legend = m
        .attractors
        .iter()
        .enumerate()
        .map(|(i, a)| format!("#{i} {}", describe(a)))
        .collect();
    Artifact::Map {
        dir: dir.into(),
        stem: stem.into(),
        map: CategoryMap {
            title: title.into(),
            caption: Some(format!(
                "{}, {}×{} initial conditions in [-2, 2]²",
                pt.caption(),
                m.grid.n,
                m.grid.n
            )),
            x_label: "q(0) (dimensionless)".into(),
            y_label: "q'(0) (dimensionless)".into(),
            x: (m.grid.lo, m.grid.hi, m.grid.n),
            y: (m.grid.lo, m.grid.hi, m.grid.n),
            cells: m.labels.iter().map(|&l| Some(l)).collect(),
            legend,
        },
    }
}

fn chaos_figure(pt: Point, m: &AttractorMap) -> Result<Artifact> {
    let flow = flow_of(&pt)?;
    let a = m
        .attractors
        .iter()
        .find(|a| a.steady.motion == Motion::Chaotic)
        .or_else(|| dominant(m));
    let panels = match a {
        Some(a) => {
            // What the motion is goes into the caption: the panel titles stay short enough
            // not to run into each other.
            let escape = a
                .escape
                .as_ref()
                .filter(|r| r.escapes > 0)
                .map_or(String::new(), |r| format!(", κ = {:.1e}/period", r.rate));
            let caption = format!(
                "F_m {}, F_ah {}, ζ {}, Ω {}; {}, λ = {:+.4}{escape}",
                pt.fm,
                pt.fah,
                pt.zeta,
                pt.omega,
                motion_name(a),
                a.steady.lyapunov.unwrap_or(f64::NAN)
            );
            let f = steady_figures(&flow, &a.steady, &caption)?;
            vec![f.history, f.poincare]
        }
        None => Vec::new(),
    };
    Ok(Artifact::Panels {
        dir: DIR.into(),
        stem: "fig04-chaos".into(),
        title: "Fig. 4: chaotic response, (a) time history, (b) Poincaré map".into(),
        panels,
        cols: 2,
    })
}

/// Time histories of the attractor of the stated period (else the chaotic set, else the dominant
/// attractor) at each point.
fn histories(
    stem: &str,
    title: &str,
    maps: &[(Point, &AttractorMap, Option<u32>)],
) -> Result<Artifact> {
    let mut panels = Vec::new();
    for (pt, m, want) in maps {
        // The stated period; else the chaotic set when there is one (what the paper drew, a
        // transient or not), else the largest basin.
        let a = match want {
            Some(p) => m.attractors.iter().find(|a| a.steady.period == Some(*p)),
            None => m
                .attractors
                .iter()
                .find(|a| a.steady.motion == Motion::Chaotic),
        }
        .or_else(|| dominant(m));
        if let Some(a) = a {
            let flow = flow_of(pt)?;
            let n = periods_to_draw(&a.steady).max(8);
            let s = orbit_samples(&flow, &a.steady, n)?;
            panels.push(XyPlot {
                title: format!(
                    "F_hat = {:.2}, zeta = {}: {}, basin {:.1}%",
                    pt.fm / pt.fah,
                    pt.zeta,
                    name(a),
                    100.0 * a.basin_fraction
                ),
                caption: Some(pt.caption()),
                x_label: "t (dimensionless)".into(),
                y_label: "q".into(),
                series: vec![Series::line("q(t)", s.iter().map(|x| (x.t, x.q)).collect())],
                legend: false,
                ..XyPlot::default()
            });
        }
    }
    Ok(Artifact::Panels {
        dir: DIR.into(),
        stem: stem.into(),
        title: title.into(),
        panels,
        cols: 2,
    })
}

/// Fig. 9's impact regimes, drawn with the three coexisting attractors of Omega_h 0.5.
fn impact_regimes(pt: Point, m: &AttractorMap) -> Result<Artifact> {
    let flow = flow_of(&pt)?;
    let mut panels = Vec::new();
    for a in &m.attractors {
        let s = orbit_samples(&flow, &a.steady, 2 * a.steady.period.unwrap_or(20) as usize)?;
        let (t0, t1) = (
            s.first().map_or(0.0, |x| x.t),
            s.last().map_or(1.0, |x| x.t),
        );
        panels.push(XyPlot {
            title: format!(
                "case {}: {}",
                a.steady.impact.roman(),
                impact_name(a.steady.impact)
            ),
            caption: Some(pt.caption()),
            x_label: "t (dimensionless)".into(),
            y_label: "q (dimensionless)".into(),
            series: vec![
                Series::line("q(t)", s.iter().map(|x| (x.t, x.q)).collect()),
                Series::dashed("q = 1", vec![(t0, 1.0), (t1, 1.0)]).with_color(7),
                Series::dashed("q = -1", vec![(t0, -1.0), (t1, -1.0)]).with_color(7),
            ],
            ..XyPlot::default()
        });
    }
    Ok(Artifact::Panels {
        dir: DIR.into(),
        stem: "fig09-impact-regimes".into(),
        title: "Fig. 9: impact regimes (case I, II, III), shown by the coexisting attractors of Fig. 2(b)".into(),
        panels,
        cols: 3,
    })
}
