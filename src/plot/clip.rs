//! Geometry done before handing data to the backend: clipping to the axis box (plotters clamps
//! out-of-range points onto the border instead of clipping), breaking lines at non-finite points,
//! and dropping points that would land on the same pixel (keeps SVG output small).

use std::collections::HashSet;

type P = (f64, f64);

/// The visible data rectangle and its size in pixels.
#[derive(Debug, Clone, Copy)]
pub(crate) struct View {
    pub x: (f64, f64),
    pub y: (f64, f64),
    pub px: (u32, u32),
}

impl View {
    fn contains(&self, (x, y): P) -> bool {
        x >= self.x.0 && x <= self.x.1 && y >= self.y.0 && y <= self.y.1
    }

    /// Data size of one pixel along each axis.
    pub fn pixel(&self) -> P {
        (
            (self.x.1 - self.x.0) / f64::from(self.px.0.max(1)),
            (self.y.1 - self.y.0) / f64::from(self.px.1.max(1)),
        )
    }
}

/// Liang-Barsky clipping of segment a-b; returns the visible part and whether each end was cut.
fn clip_segment(a: P, b: P, v: &View) -> Option<(P, P, bool, bool)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - v.x.0),
        (dx, v.x.1 - a.0),
        (-dy, a.1 - v.y.0),
        (dy, v.y.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                if r > t1 {
                    return None;
                }
                t0 = t0.max(r);
            } else {
                if r < t0 {
                    return None;
                }
                t1 = t1.min(r);
            }
        }
    }
    let at = |t: f64| (a.0 + t * dx, a.1 + t * dy);
    let s = if t0 > 0.0 { at(t0) } else { a };
    let e = if t1 < 1.0 { at(t1) } else { b };
    Some((s, e, t0 > 0.0, t1 < 1.0))
}

/// Drops points closer than half a pixel (on both axes) to the last kept point.
fn thin(line: Vec<P>, v: &View) -> Vec<P> {
    let (tx, ty) = v.pixel();
    let (tx, ty) = (0.5 * tx, 0.5 * ty);
    let n = line.len();
    let mut out: Vec<P> = Vec::with_capacity(n.min(4096));
    for (i, p) in line.into_iter().enumerate() {
        match out.last() {
            Some(&q) if i + 1 < n && (p.0 - q.0).abs() < tx && (p.1 - q.1).abs() < ty => {}
            _ => out.push(p),
        }
    }
    out
}

/// Visible polylines of a line series: broken at non-finite points, clipped to the view and
/// thinned. An isolated finite point inside the view comes back as a one-point polyline.
pub(crate) fn polylines(points: &[P], v: &View) -> Vec<Vec<P>> {
    let finite = |p: &P| p.0.is_finite() && p.1.is_finite();
    let mut out = Vec::new();
    let mut cur: Vec<P> = Vec::new();
    let mut flush = |cur: &mut Vec<P>| {
        if !cur.is_empty() {
            out.push(thin(std::mem::take(cur), v));
        }
    };
    for (i, &a) in points.iter().enumerate() {
        if !finite(&a) {
            continue;
        }
        let prev_ok = i > 0 && finite(&points[i - 1]);
        let next = points.get(i + 1).filter(|p| finite(p));
        if !prev_ok && next.is_none() && v.contains(a) {
            flush(&mut cur);
            cur.push(a);
            flush(&mut cur);
            continue;
        }
        let Some(&b) = next else {
            flush(&mut cur);
            continue;
        };
        match clip_segment(a, b, v) {
            None => flush(&mut cur),
            Some((s, e, cut_start, cut_end)) => {
                if cut_start || cur.is_empty() {
                    flush(&mut cur);
                    cur.push(s);
                }
                cur.push(e);
                if cut_end {
                    flush(&mut cur);
                }
            }
        }
    }
    flush(&mut cur);
    out
}

/// Finite points inside the view, at most one per pixel.
pub(crate) fn visible_points(points: &[P], v: &View) -> Vec<P> {
    let (px, py) = v.pixel();
    let mut seen = HashSet::new();
    points
        .iter()
        .copied()
        .filter(|&p| p.0.is_finite() && p.1.is_finite() && v.contains(p))
        .filter(|p| {
            let key = (
                ((p.0 - v.x.0) / px).floor() as i64,
                ((p.1 - v.y.0) / py).floor() as i64,
            );
            seen.insert(key)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const V: View = View {
        x: (0.0, 10.0),
        y: (0.0, 10.0),
        px: (1000, 1000),
    };

    #[test]
    fn lines_break_at_nan_and_clip_at_border() {
        let pts = [
            (1.0, 1.0),
            (2.0, 2.0),
            (f64::NAN, 0.0),
            (3.0, 3.0),
            (20.0, 3.0),
        ];
        let lines = polylines(&pts, &V);
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0], vec![(1.0, 1.0), (2.0, 2.0)]);
        assert_eq!(lines[1], vec![(3.0, 3.0), (10.0, 3.0)]);
    }

    #[test]
    fn line_leaving_and_reentering_gives_two_pieces() {
        let pts = [(5.0, 5.0), (5.0, 15.0), (6.0, 5.0)];
        let lines = polylines(&pts, &V);
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0], vec![(5.0, 5.0), (5.0, 10.0)]);
    }

    #[test]
    fn isolated_points_and_thinning() {
        assert_eq!(polylines(&[(1.0, 1.0)], &V), vec![vec![(1.0, 1.0)]]);
        assert!(polylines(&[(11.0, 1.0)], &V).is_empty());
        let dense: Vec<P> = (0..=10_000).map(|i| (i as f64 * 1e-3, 1.0)).collect();
        let lines = polylines(&dense, &V);
        assert!(lines[0].len() < 2100);
        assert_eq!(*lines[0].last().unwrap(), (10.0, 1.0));
        assert_eq!(visible_points(&dense, &V).len(), 1001);
    }
}
