//! Marker mode: each connected blob of matching pixels (4-connectivity) is one data point at its
//! centroid, e.g. the squares of Munro's curves ("- - □ - -") in the paper's Figs 19-22.

use super::mask::Mask;

/// Which blobs count as markers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MarkerFilter {
    /// Blobs with fewer pixels are ignored (specks, stray anti-aliasing, dash ends).
    pub min_area: usize,
    /// Blobs with more pixels are ignored (e.g. a solid curve of the same colour).
    pub max_area: Option<usize>,
    /// Bounding-box width and height, in pixels, that a marker must both lie within
    /// (`min`, `max`); rejects thin dashes and long lines of the marker colour.
    pub size: Option<(u32, u32)>,
    /// Erosion radius in pixels applied before the blobs are found: a pixel stays only if the
    /// whole (2r+1) x (2r+1) square around it matches. Detaches filled markers from thin lines
    /// of the same colour (lines thinner than 2r+1 vanish); hollow markers need 0.
    pub erode: u32,
}

impl Default for MarkerFilter {
    fn default() -> Self {
        MarkerFilter {
            min_area: 4,
            max_area: None,
            size: None,
            erode: 0,
        }
    }
}

/// One connected blob.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Blob {
    area: usize,
    sum: (f64, f64),
    min: (usize, usize),
    max: (usize, usize),
}

impl Blob {
    /// The blob made of both: areas and pixel sums add, bounding boxes join.
    fn union(&self, o: &Blob) -> Blob {
        Blob {
            area: self.area + o.area,
            sum: (self.sum.0 + o.sum.0, self.sum.1 + o.sum.1),
            min: (self.min.0.min(o.min.0), self.min.1.min(o.min.1)),
            max: (self.max.0.max(o.max.0), self.max.1.max(o.max.1)),
        }
    }

    fn box_area(&self) -> usize {
        (self.max.0 - self.min.0 + 1) * (self.max.1 - self.min.1 + 1)
    }

    fn accepted(&self, f: &MarkerFilter) -> bool {
        let (w, h) = (self.max.0 - self.min.0 + 1, self.max.1 - self.min.1 + 1);
        let size_ok = f.size.is_none_or(|(lo, hi)| {
            let inside = |s: usize| s >= lo as usize && s <= hi as usize;
            inside(w) && inside(h)
        });
        self.area >= f.min_area && f.max_area.is_none_or(|m| self.area <= m) && size_ok
    }
}

/// Marker sizes found in a figure: how many blobs (of at least the filter's minimum area and at
/// most its maximum) have each bounding-box size (the larger of width and height, in pixels),
/// and the size range picked as the markers'.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MarkerSizes {
    /// (size, number of blobs), by increasing size.
    pub histogram: Vec<(u32, usize)>,
    /// The most common size +-1 pixel (+-2 from 8 pixels up), for anti-aliased edges.
    pub picked: Option<(u32, u32)>,
}

/// The blob-size histogram of `mask` under `filter` (its size bounds ignored) and the picked
/// size range.
pub(crate) fn marker_sizes(mask: &Mask, filter: &MarkerFilter) -> MarkerSizes {
    let any = MarkerFilter {
        size: None,
        ..*filter
    };
    let mut hist = std::collections::BTreeMap::new();
    for b in blobs(mask, filter.erode)
        .iter()
        .filter(|b| b.accepted(&any))
    {
        let s = (b.max.0 - b.min.0 + 1).max(b.max.1 - b.min.1 + 1) as u32;
        *hist.entry(s).or_insert(0usize) += 1;
    }
    let histogram: Vec<(u32, usize)> = hist.into_iter().collect();
    // The size with the most blobs within +-1 of it (anti-aliasing spreads one marker size).
    let near = |s: u32| {
        histogram
            .iter()
            .filter(|(t, _)| t.abs_diff(s) <= 1)
            .map(|h| h.1)
            .sum::<usize>()
    };
    let picked = histogram
        .iter()
        .max_by_key(|&&(s, n)| (near(s), n))
        .map(|&(s, _)| {
            let r = if s >= 8 { 2 } else { 1 };
            (s.saturating_sub(r).max(1), s + r)
        });
    MarkerSizes { histogram, picked }
}

/// What marker extraction found: the markers' pixel positions and why the other blobs were left
/// out, so that a caller can say where the missing points went.
#[derive(Debug, Clone, PartialEq)]
pub struct MarkerCensus {
    /// Pixel-space centres (column, row) of the markers that pass the filter.
    pub points: Vec<(f64, f64)>,
    /// Connected blobs of the colour found (after erosion), before any filtering.
    pub blobs: usize,
    /// Markers among `points` put back together from two or more pieces.
    pub rejoined: usize,
    /// Candidates left out for having fewer pixels than the minimum area.
    pub too_small: usize,
    /// Candidates left out for having more pixels than the maximum area.
    pub too_large: usize,
    /// Candidates left out because a side of their bounding box lies outside the size bounds.
    pub off_size: usize,
}

impl MarkerCensus {
    /// What was left out and why, e.g. "3 left out: 2 smaller than the minimum area, 1 with a
    /// side outside the size bounds (a marker mostly hidden under another curve, or a line)".
    pub fn left_out_text(&self) -> String {
        let reasons: Vec<String> = [
            (self.too_small, "smaller than the minimum area"),
            (self.too_large, "larger than the maximum area"),
            (
                self.off_size,
                "with a side outside the size bounds (a marker partly hidden under another \
                 curve, or a line)",
            ),
        ]
        .iter()
        .filter(|r| r.0 > 0)
        .map(|(n, why)| format!("{n} {why}"))
        .collect();
        let total = self.too_small + self.too_large + self.off_size;
        if total == 0 {
            "none left out".to_string()
        } else {
            format!("{total} left out: {}", reasons.join(", "))
        }
    }
}

/// The markers of `mask` under `filter`.
///
/// A marker drawn under another curve is cut into pieces by it (in geardyn's own reports the
/// model lines cross every measured square). With size bounds `(lo, hi)` given, pieces that fail
/// the size bounds on their own are joined, in column order, with neighbouring pieces as long as
/// the joined bounding box stays within `hi` x `hi`; a blob that passes on its own is never
/// joined, so a figure with clean markers gives the same points as without this step. A single
/// blob is placed at its centroid; a rejoined marker at the centre of its bounding box, because
/// the part hidden under the other curve would pull the centroid of the visible pixels aside.
pub(crate) fn marker_census(mask: &Mask, filter: &MarkerFilter) -> MarkerCensus {
    let blobs = blobs(mask, filter.erode);
    let found = blobs.len();
    let candidates = match filter.size {
        Some((_, hi)) => rejoin(blobs, filter, hi as usize),
        None => blobs.into_iter().map(|b| (b, 1)).collect(),
    };
    let (x0, y0) = (f64::from(mask.region.x.0), f64::from(mask.region.y.0));
    let mut census = MarkerCensus {
        points: Vec::new(),
        blobs: found,
        rejoined: 0,
        too_small: 0,
        too_large: 0,
        off_size: 0,
    };
    for (b, pieces) in candidates {
        if b.area < filter.min_area {
            census.too_small += 1;
        } else if filter.max_area.is_some_and(|m| b.area > m) {
            census.too_large += 1;
        } else if !b.accepted(filter) {
            census.off_size += 1;
        } else if pieces > 1 {
            census.rejoined += 1;
            let centre = |lo: usize, hi: usize| (lo + hi) as f64 / 2.0;
            census
                .points
                .push((x0 + centre(b.min.0, b.max.0), y0 + centre(b.min.1, b.max.1)));
        } else {
            let n = b.area as f64;
            census.points.push((x0 + b.sum.0 / n, y0 + b.sum.1 / n));
        }
    }
    census
}

/// The blobs with the pieces of cut markers joined (see [`marker_census`]), each with its number
/// of pieces, in column order.
fn rejoin(mut blobs: Vec<Blob>, filter: &MarkerFilter, hi: usize) -> Vec<(Blob, usize)> {
    blobs.sort_by_key(|b| (b.min.0, b.min.1));
    let mut done: Vec<(Blob, usize)> = Vec::with_capacity(blobs.len());
    // Groups of pieces that may still take another piece: their union spans at most `hi`.
    let mut open: Vec<(Blob, usize)> = Vec::new();
    for b in blobs {
        // Pieces come in column order: a group starting more than `hi` columns before this
        // piece can take no further piece.
        let (closed, still): (Vec<_>, Vec<_>) =
            open.into_iter().partition(|g| g.0.min.0 + hi < b.min.0);
        done.extend(closed);
        open = still;
        if b.accepted(filter) {
            done.push((b, 1));
            continue;
        }
        let fits = |g: &Blob| {
            let u = g.union(&b);
            u.max.0 - u.min.0 < hi && u.max.1 - u.min.1 < hi
        };
        let best = open
            .iter_mut()
            .filter(|g| fits(&g.0))
            .min_by_key(|g| g.0.union(&b).box_area());
        match best {
            Some(g) => *g = (g.0.union(&b), g.1 + 1),
            None => open.push((b, 1)),
        }
    }
    done.extend(open);
    done
}

/// The 4-connected blobs of `mask` after erosion by `erode` pixels.
fn blobs(mask: &Mask, erode_by: u32) -> Vec<Blob> {
    let on = erode(mask, erode_by);
    let (w, h) = (mask.width(), mask.height());
    let mut seen = vec![false; on.len()];
    let mut stack = Vec::new();
    let mut blobs = Vec::new();
    for start in 0..on.len() {
        if !on[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let mut b = Blob {
            area: 0,
            sum: (0.0, 0.0),
            min: (usize::MAX, usize::MAX),
            max: (0, 0),
        };
        while let Some(i) = stack.pop() {
            let (c, r) = (i % w, i / w);
            b.area += 1;
            b.sum = (b.sum.0 + c as f64, b.sum.1 + r as f64);
            b.min = (b.min.0.min(c), b.min.1.min(r));
            b.max = (b.max.0.max(c), b.max.1.max(r));
            let neighbours = [
                (c > 0).then(|| i - 1),
                (c + 1 < w).then(|| i + 1),
                (r > 0).then(|| i - w),
                (r + 1 < h).then(|| i + w),
            ];
            for j in neighbours.into_iter().flatten() {
                if on[j] && !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        blobs.push(b);
    }
    blobs
}

/// The mask eroded by a (2r+1)-square (separable: rows, then columns); pixels outside the region
/// count as not matching.
fn erode(mask: &Mask, r: u32) -> Vec<bool> {
    if r == 0 {
        return mask.on.clone();
    }
    let r = r as usize;
    let (w, h) = (mask.width(), mask.height());
    // Along one line of `n` cells: cell k survives if cells k-r ..= k+r all match.
    let pass = |get: &dyn Fn(usize) -> bool, n: usize, out: &mut dyn FnMut(usize, bool)| {
        let mut run = 0usize; // matching cells ending at k + r
        for k in 0..n + r {
            run = if k < n && get(k) { run + 1 } else { 0 };
            if k >= r {
                let centre = k - r;
                out(centre, centre >= r && run > 2 * r);
            }
        }
    };
    let mut rows = vec![false; w * h];
    for y in 0..h {
        pass(&|k| mask.on[y * w + k], w, &mut |k, v| rows[y * w + k] = v);
    }
    let mut out = vec![false; w * h];
    for x in 0..w {
        pass(&|k| rows[k * w + x], h, &mut |k, v| out[k * w + x] = v);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::mask::Region;
    use super::*;

    fn marker_points(m: &Mask, f: &MarkerFilter) -> Vec<(f64, f64)> {
        marker_census(m, f).points
    }

    fn mask(rows: &[&str]) -> Mask {
        let (w, h) = (rows[0].len() as u32, rows.len() as u32);
        Mask {
            region: Region {
                x: (100, 100 + w),
                y: (50, 50 + h),
            },
            on: rows
                .iter()
                .flat_map(|r| r.bytes().map(|b| b == b'#'))
                .collect(),
        }
    }

    const PICTURE: [&str; 7] = [
        "###.......#",
        "###........",
        "###..#.....",
        "......####.",
        ".#.........",
        "........###",
        "#######.###",
    ];

    #[test]
    fn blobs_are_4_connected_and_filtered() {
        let m = mask(&PICTURE);
        let all = MarkerFilter {
            min_area: 1,
            ..MarkerFilter::default()
        };
        let MarkerCensus {
            points: pts,
            blobs: n,
            ..
        } = marker_census(&m, &all);
        assert_eq!(n, 7);
        assert_eq!(pts.len(), 7);
        assert_eq!(pts[0], (101.0, 51.0));

        let big = MarkerFilter {
            min_area: 4,
            ..MarkerFilter::default()
        };
        let pts = marker_points(&m, &big);
        // the 3x3 square, the dash (4), the 3x2 block and the bottom line (7).
        assert_eq!(pts.len(), 4);

        let squares = MarkerFilter {
            min_area: 4,
            size: Some((2, 3)),
            ..MarkerFilter::default()
        };
        let pts = marker_points(&m, &squares);
        assert_eq!(pts, [(101.0, 51.0), (109.0, 55.5)]);

        let capped = MarkerFilter {
            min_area: 4,
            max_area: Some(6),
            ..MarkerFilter::default()
        };
        assert_eq!(marker_points(&m, &capped).len(), 2);
    }

    #[test]
    fn sizes_histogram_picks_the_common_size() {
        let m = mask(&PICTURE);
        let s = marker_sizes(&m, &MarkerFilter::default());
        // Blobs of area >= 4: the 3x3 square (3), the 4-long dash (4), the 3x2 block (3), the
        // bottom line (7).
        assert_eq!(s.histogram, [(3, 2), (4, 1), (7, 1)]);
        assert_eq!(s.picked, Some((2, 4)));
    }

    #[test]
    fn erosion_detaches_a_filled_marker_from_a_thin_line() {
        let m = mask(&[
            "...........",
            "....###....",
            "....###....",
            "#######....",
            "....###....",
            "....###....",
            "...........",
        ]);
        let f = MarkerFilter {
            min_area: 1,
            erode: 1,
            ..MarkerFilter::default()
        };
        let MarkerCensus {
            points: pts,
            blobs: n,
            ..
        } = marker_census(&m, &f);
        assert_eq!(n, 1);
        assert_eq!(pts, [(105.0, 53.0)]);
        // Without erosion the line and the square are one blob, pulled towards the line.
        let pts = marker_points(&m, &MarkerFilter::default());
        assert_eq!(pts.len(), 1);
        assert_ne!(pts[0], (105.0, 53.0));
    }

    #[test]
    fn pieces_of_a_cut_marker_are_rejoined_and_whole_markers_are_not() {
        // A 5 x 5 marker cut by a one-column line of another colour (column 3), and a whole
        // 5 x 5 marker right beside it.
        let m = mask(&[
            "##.##..#####",
            "##.##..#####",
            "##.##..#####",
            "##.##..#####",
            "##.##..#####",
        ]);
        let f = MarkerFilter {
            min_area: 4,
            size: Some((4, 6)),
            ..MarkerFilter::default()
        };
        let c = marker_census(&m, &f);
        assert_eq!((c.blobs, c.rejoined, c.off_size), (3, 1, 0));
        // The rejoined marker sits at its bounding box's centre, the whole one at its centroid.
        assert_eq!(c.points, [(102.0, 52.0), (109.0, 52.0)]);
        // Without size bounds nothing is rejoined: the pieces are too thin for no filter.
        let c = marker_census(&m, &MarkerFilter::default());
        assert_eq!((c.points.len(), c.rejoined), (3, 0));
        // Bounds a piece cannot reach even when joined leave the pieces out, counted.
        let small = MarkerFilter {
            size: Some((2, 3)),
            ..f
        };
        let c = marker_census(&m, &small);
        assert_eq!((c.points.len(), c.off_size), (0, 3));
        assert!(
            c.left_out_text().starts_with("3 left out"),
            "{}",
            c.left_out_text()
        );
    }
}
