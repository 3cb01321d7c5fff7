//! Lines drawn on top of each other: a series whose line lies under another's is listed in the
//! legend but invisible, so the legend says which lines coincide, and where they part.

use std::collections::HashSet;

use super::clip::View;

/// Share of a line's length that must lie on another line for the two to be noted as coinciding
/// in part, and for them to coincide outright.
const PARTLY: f64 = 0.75;
const WHOLLY: f64 = 0.97;
/// Most notes kept (the pairs that share the most), so that notes never crowd the legend.
const MAX_NOTES: usize = 3;

/// One drawn series: its label, visible polylines and markers (data coordinates).
pub(crate) struct Drawn<'a> {
    pub label: &'a str,
    pub lines: &'a [Vec<(f64, f64)>],
    pub dots: &'a [(f64, f64)],
}

/// Points every `step` pixels along the lines of `d`, and its markers, as (pixel column, pixel
/// row, data x).
fn samples(d: &Drawn<'_>, view: &View, step: f64) -> Vec<(i32, i32, f64)> {
    let (px, py) = view.pixel();
    let to_px = |p: (f64, f64)| ((p.0 - view.x.0) / px, (view.y.1 - p.1) / py);
    let lines = d.lines;
    let mut out: Vec<(i32, i32, f64)> = d
        .dots
        .iter()
        .map(|&p| {
            let (u, v) = to_px(p);
            (u.round() as i32, v.round() as i32, p.0)
        })
        .collect();
    for l in lines {
        for s in l.windows(2) {
            let (a, b) = (to_px(s[0]), to_px(s[1]));
            let n = ((b.0 - a.0).hypot(b.1 - a.1) / step)
                .ceil()
                .clamp(1.0, 100_000.0) as usize;
            for k in 0..n {
                let t = k as f64 / n as f64;
                let (u, v) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                out.push((
                    u.round() as i32,
                    v.round() as i32,
                    s[0].0 + t * (s[1].0 - s[0].0),
                ));
            }
        }
    }
    out
}

/// Share of `a`'s samples within `r` pixels of a pixel of `b`, and the x extent of the others.
fn covered(a: &[(i32, i32, f64)], b: &HashSet<(i32, i32)>, r: i32) -> (f64, Option<(f64, f64)>) {
    let near = |&(u, v, _): &(i32, i32, f64)| {
        (-r..=r).any(|du| (-r..=r).any(|dv| b.contains(&(u + du, v + dv))))
    };
    let mut apart: Option<(f64, f64)> = None;
    let mut hits = 0usize;
    for s in a {
        if near(s) {
            hits += 1;
        } else {
            apart = Some(apart.map_or((s.2, s.2), |(lo, hi)| (lo.min(s.2), hi.max(s.2))));
        }
    }
    (hits as f64 / a.len().max(1) as f64, apart)
}

/// Notes on the pairs of series (lines or markers) that coincide on the canvas: "A and B
/// coincide", or "A and B coincide except at x lo–hi" when one lies on the other for at least
/// three quarters of its length; at most [`MAX_NOTES`], the most shared first.
/// `fmt` formats x values; `unit`, when the x axis has one, follows them ("4375–4748 rpm").
pub(crate) fn coincidence_notes(
    drawn: &[Drawn<'_>],
    view: &View,
    fmt: impl Fn(f64) -> String,
    unit: Option<&str>,
) -> Vec<String> {
    let sampled: Vec<_> = drawn.iter().map(|d| samples(d, view, 2.0)).collect();
    let cells: Vec<HashSet<(i32, i32)>> = drawn
        .iter()
        .map(|d| {
            samples(d, view, 0.5)
                .into_iter()
                .map(|(u, v, _)| (u, v))
                .collect()
        })
        .collect();
    let mut notes = Vec::new();
    for i in 0..drawn.len() {
        for j in i + 1..drawn.len() {
            if sampled[i].len() < 10 || sampled[j].len() < 10 {
                continue;
            }
            // Lines hide lines, markers hide markers; a marker on a line hides neither.
            let (li, lj) = (drawn[i].lines.is_empty(), drawn[j].lines.is_empty());
            if li != lj {
                continue;
            }
            // Lines are 2 px wide; a marker hides another within about its radius.
            let r = if li { 2 } else { 1 };
            let (ci, apart_i) = covered(&sampled[i], &cells[j], r);
            let (cj, apart_j) = covered(&sampled[j], &cells[i], r);
            let (share, apart) = if ci >= cj {
                (ci, apart_i)
            } else {
                (cj, apart_j)
            };
            let (a, b) = (drawn[i].label, drawn[j].label);
            match apart {
                _ if share >= WHOLLY => notes.push((share, format!("{a} and {b} coincide"))),
                Some((lo, hi)) if share >= PARTLY => {
                    let (lo, hi) = (fmt(lo), fmt(hi));
                    let at = if lo == hi { lo } else { format!("{lo}–{hi}") };
                    let at = match unit {
                        Some(u) => format!("{at} {u}"),
                        None => at,
                    };
                    notes.push((share, format!("{a} and {b} coincide except at {at}")));
                }
                _ => {}
            }
        }
    }
    notes.sort_by(|a, b| b.0.total_cmp(&a.0));
    notes.into_iter().take(MAX_NOTES).map(|n| n.1).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const V: View = View {
        x: (0.0, 10.0),
        y: (0.0, 10.0),
        px: (500, 500),
    };

    fn line(f: impl Fn(f64) -> f64) -> Vec<Vec<(f64, f64)>> {
        vec![(0..=100)
            .map(|i| (i as f64 * 0.1, f(i as f64 * 0.1)))
            .collect()]
    }

    fn notes(a: &[Vec<(f64, f64)>], b: &[Vec<(f64, f64)>]) -> Vec<String> {
        notes_with_unit(a, b, None)
    }

    fn notes_with_unit(
        a: &[Vec<(f64, f64)>],
        b: &[Vec<(f64, f64)>],
        unit: Option<&str>,
    ) -> Vec<String> {
        let d = [
            Drawn {
                label: "up",
                lines: a,
                dots: &[],
            },
            Drawn {
                label: "down",
                lines: b,
                dots: &[],
            },
        ];
        coincidence_notes(&d, &V, |x| format!("{x:.1}"), unit)
    }

    type Lines = Vec<Vec<(f64, f64)>>;

    /// The two sweeps of a hysteresis loop: apart between x = 4 and 6.
    fn hysteresis() -> (Lines, Lines) {
        let up = line(|x| x.min(5.0));
        let down = line(|x| {
            if (4.0..6.0).contains(&x) {
                8.0
            } else {
                x.min(5.0)
            }
        });
        (up, down)
    }

    #[test]
    fn identical_lines_coincide() {
        let a = line(|x| 0.5 * x);
        assert_eq!(notes(&a, &a), ["up and down coincide"]);
        // Within a pixel (0.02 data units) still the same line on the canvas.
        assert_eq!(
            notes(&a, &line(|x| 0.5 * x + 0.01)),
            ["up and down coincide"]
        );
    }

    #[test]
    fn lines_that_part_say_where() {
        let (up, down) = hysteresis();
        let n = notes(&up, &down);
        assert_eq!(n.len(), 1, "{n:?}");
        let range = n[0]
            .strip_prefix("up and down coincide except at ")
            .unwrap();
        let (lo, hi) = range.split_once('–').unwrap();
        let (lo, hi): (f64, f64) = (lo.parse().unwrap(), hi.parse().unwrap());
        assert!(
            (3.8..=4.1).contains(&lo) && (5.8..=6.1).contains(&hi),
            "{n:?}"
        );
    }

    #[test]
    fn markers_on_the_same_points_coincide() {
        let pts: Vec<(f64, f64)> = (0..20).map(|i| (i as f64 * 0.5, 3.0)).collect();
        let d = [
            Drawn {
                label: "sweep",
                lines: &[],
                dots: &pts,
            },
            Drawn {
                label: "attractors",
                lines: &[],
                dots: &pts,
            },
        ];
        let n = coincidence_notes(&d, &V, |x| format!("{x:.1}"), None);
        assert_eq!(n, ["sweep and attractors coincide"]);
    }

    /// The axis unit follows the range once, not each end.
    #[test]
    fn a_range_states_the_axis_unit_once() {
        let (up, down) = hysteresis();
        let n = notes_with_unit(&up, &down, Some("rpm"));
        assert_eq!(n.len(), 1, "{n:?}");
        assert!(
            n[0].ends_with(" rpm") && n[0].matches("rpm").count() == 1,
            "{n:?}"
        );
    }

    #[test]
    fn separate_lines_get_no_note() {
        assert!(notes(&line(|x| x), &line(|x| 10.0 - x)).is_empty());
        assert!(notes(&line(|_| 2.0), &line(|_| 3.0)).is_empty());
    }
}
