//! Bounding boxes: hfp's `-b` and `-g` forms (SPEC §5) and automatic extent detection.

use frep_core::eval::interval::{Interval, IntervalEval};
use frep_core::eval::Inputs;
use frep_core::Model;

use super::Resolution;

/// hfp's default box, `-10..10` on each axis.
pub const HFP_DEFAULT: [f64; 6] = [-10.0, -10.0, -10.0, 10.0, 10.0, 10.0];

fn numbers(s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .map(|t| {
            let t = t.trim();
            t.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("not a number: {t:?}"))
        })
        .collect()
}

/// Parses a box in one of hfp's `-b` forms: `v` (±|v| on every axis), `min,max` (the same
/// range on every axis), `xs,ys,zs` (±|each|) or `x0,y0,z0,x1,y1,z1`.
pub fn parse_box(s: &str) -> Result<[f64; 6], String> {
    let v = numbers(s)?;
    let b = match v.len() {
        1 => {
            let a = v[0].abs();
            [-a, -a, -a, a, a, a]
        }
        2 => [v[0], v[0], v[0], v[1], v[1], v[1]],
        3 => {
            let a = v.map_abs();
            [-a[0], -a[1], -a[2], a[0], a[1], a[2]]
        }
        6 => [v[0], v[1], v[2], v[3], v[4], v[5]],
        n => return Err(format!("a box has 1, 2, 3 or 6 numbers, not {n}")),
    };
    if (0..3).any(|k| b[k + 3].partial_cmp(&b[k]) != Some(std::cmp::Ordering::Greater)) {
        return Err(format!("empty box {s:?}"));
    }
    Ok(b)
}

trait MapAbs {
    fn map_abs(&self) -> [f64; 3];
}

impl MapAbs for Vec<f64> {
    fn map_abs(&self) -> [f64; 3] {
        [self[0].abs(), self[1].abs(), self[2].abs()]
    }
}

/// hfp's `-g n` / `-g nx,ny,nz` (cells per axis, clamped to 2..=250 as hfp does) as a cell
/// size for `bounds`: the finest of the axes' `extent / n`.
pub fn parse_grid(s: &str, bounds: &[f64; 6]) -> Result<Resolution, String> {
    let v = numbers(s)?;
    let n: Vec<f64> = match v.len() {
        1 => vec![v[0]; 3],
        3 => v,
        k => return Err(format!("a grid has 1 or 3 numbers, not {k}")),
    };
    let cell = (0..3)
        .map(|k| (bounds[k + 3] - bounds[k]) / n[k].round().clamp(2.0, 250.0))
        .fold(f64::INFINITY, f64::min);
    Ok(Resolution::CellSize(cell))
}

/// Cells of a scan: 2^SCAN_DEPTH per axis.
const SCAN_DEPTH: u32 = 5;

/// The work [`detect`] may do, all scans together, in interval evaluations
/// times the tape's length. Interval operations cost 7–230 ns each, so that is
/// 0.1–1 s at most, and tens of milliseconds for the corpus's models. Some
/// models' interval bounds prune nothing: noise terms, machine-generated chains
/// of `atan2`. Without the budget, those refined every scan to the full depth:
/// seconds, or minutes for a long tape.
const WORK_BUDGET: usize = 8_000_000;

/// Interval evaluations of one scan at most (a short tape's budget is
/// otherwise spent on one scan).
const SCAN_EVALS: usize = 200_000;

struct Scan<'a> {
    ev: IntervalEval,
    inputs: &'a Inputs,
    lo: [f64; 3],
    hi: [f64; 3],
    /// Interval evaluations left to this scan.
    evals_left: usize,
    /// Stop at the first solid cell on the faces of this cube (a scan that
    /// only asks whether the solid lies strictly inside).
    stop_at_faces: Option<Corners>,
    /// Whether it stopped so.
    touched: bool,
}

impl Scan<'_> {
    fn visit(&mut self, lo: [f64; 3], hi: [f64; 3], depth: u32) {
        if self.touched {
            return;
        }
        if self.evals_left == 0 {
            // Out of work: count the cell as solid (the box only grows).
            self.record(lo, hi);
            return;
        }
        self.evals_left -= 1;
        let iv = self.ev.eval(
            Interval::new(lo[0], hi[0]),
            Interval::new(lo[1], hi[1]),
            Interval::new(lo[2], hi[2]),
            self.inputs,
        );
        if iv.is_outside() {
            return;
        }
        if depth == SCAN_DEPTH || iv.is_positive() {
            self.record(lo, hi);
            return;
        }
        let mid = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        for c in 0..8 {
            let l = [0, 1, 2].map(|k| if c >> k & 1 == 1 { mid[k] } else { lo[k] });
            let h = [0, 1, 2].map(|k| if c >> k & 1 == 1 { hi[k] } else { mid[k] });
            self.visit(l, h, depth + 1);
        }
    }

    fn record(&mut self, lo: [f64; 3], hi: [f64; 3]) {
        if let Some((cl, ch)) = self.stop_at_faces {
            if (0..3).any(|k| lo[k] <= cl[k] || hi[k] >= ch[k]) {
                self.touched = true;
            }
        }
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(lo[k]);
            self.hi[k] = self.hi[k].max(hi[k]);
        }
    }
}

/// A box's two corners.
type Corners = ([f64; 3], [f64; 3]);

/// Where the solid may be, within `[lo, hi]`, by interval arithmetic on a 32³ octree:
/// `None` when nowhere. Spends at most `budget` interval evaluations (and takes them off
/// it); cells left when it runs out count as solid. With `fit`, the scan stops at the first
/// solid cell on the box's faces (the solid is not strictly inside: its box is not needed).
fn scan(
    ev: IntervalEval,
    inputs: &Inputs,
    lo: [f64; 3],
    hi: [f64; 3],
    fit: bool,
    budget: &mut usize,
) -> (IntervalEval, Option<Corners>) {
    let allowed = (*budget).min(SCAN_EVALS);
    let mut s = Scan {
        ev,
        inputs,
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
        evals_left: allowed,
        stop_at_faces: fit.then_some((lo, hi)),
        touched: false,
    };
    s.visit(lo, hi, 0);
    *budget -= allowed - s.evals_left;
    let found = (s.lo[0] <= s.hi[0]).then_some((s.lo, s.hi));
    (s.ev, found)
}

/// Detects a box around the model's solid.
/// 1. Cubes `±2^k` (k = 0..=10) are scanned with interval arithmetic until the solid lies
///    strictly inside one.
/// 2. The box is then tightened by a second scan and grown by 5 % on each side.
///
/// `None` when no solid is found, or when it reaches even `±1024` (an unbounded solid such as
/// a half-space). Use an explicit box then; hfp's default is [`HFP_DEFAULT`]. All scans
/// together do a bounded amount of work (`WORK_BUDGET`). Where intervals prune nothing, the
/// budget runs out and the cells left count as solid. The answer is then `None` within
/// milliseconds.
pub fn detect(model: &Model, inputs: &Inputs) -> Option<[f64; 6]> {
    let tape = model.tape();
    let mut budget = WORK_BUDGET / tape.len().max(1);
    let mut ev = IntervalEval::new(&tape);
    for k in 0..=10 {
        let l = (1u32 << k) as f64;
        let (e, found) = scan(ev, inputs, [-l; 3], [l; 3], true, &mut budget);
        ev = e;
        let Some((lo, hi)) = found else {
            continue;
        };
        if (0..3).any(|a| lo[a] <= -l || hi[a] >= l) {
            if budget == 0 {
                // Every larger cube would only be counted solid whole.
                return None;
            }
            continue;
        }
        let (lo, hi) = scan(ev, inputs, lo, hi, false, &mut budget)
            .1
            .unwrap_or((lo, hi));
        let pad = (0..3).map(|a| hi[a] - lo[a]).fold(0.0f64, f64::max) * 0.05;
        return Some([
            lo[0] - pad,
            lo[1] - pad,
            lo[2] - pad,
            hi[0] + pad,
            hi[1] + pad,
            hi[2] + pad,
        ]);
    }
    None
}

/// Where a model's box came from ([`model_box`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BoxOrigin {
    /// The source's `-- bounds:` comment line.
    Comment,
    /// The solid's extent found by [`detect`].
    Extent,
    /// hfp's default [`HFP_DEFAULT`] (no extent found: an unbounded solid, or none).
    Default,
}

impl BoxOrigin {
    /// `comment`, `extent` or `default` (the wire's `boundsOrigin`).
    pub fn as_str(self) -> &'static str {
        match self {
            BoxOrigin::Comment => "comment",
            BoxOrigin::Extent => "extent",
            BoxOrigin::Default => "default",
        }
    }
}

/// The `-- bounds: …` line among the comment lines heading a model's source (any of
/// [`parse_box`]'s forms), if there is one and it parses.
pub fn bounds_from_source(source: &str) -> Option<[f64; 6]> {
    source
        .lines()
        .take_while(|l| l.trim_start().starts_with("--") || l.trim().is_empty())
        .find_map(|l| l.trim_start().strip_prefix("-- bounds:"))
        .and_then(|b| parse_box(b.trim()).ok())
}

/// The box a model is worked in when none is given: its source's `-- bounds:` line, else
/// its detected extent ([`detect`]), else [`HFP_DEFAULT`]. The one rule of the command
/// line and the server.
pub fn model_box(source: &str, model: &Model, inputs: &Inputs) -> ([f64; 6], BoxOrigin) {
    if let Some(b) = bounds_from_source(source) {
        return (b, BoxOrigin::Comment);
    }
    match detect(model, inputs) {
        Some(b) => (b, BoxOrigin::Extent),
        None => (HFP_DEFAULT, BoxOrigin::Default),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_forms() {
        assert_eq!(parse_box("2").unwrap(), [-2.0, -2.0, -2.0, 2.0, 2.0, 2.0]);
        assert_eq!(
            parse_box("-1,3").unwrap(),
            [-1.0, -1.0, -1.0, 3.0, 3.0, 3.0]
        );
        assert_eq!(
            parse_box("1,2,-3").unwrap(),
            [-1.0, -2.0, -3.0, 1.0, 2.0, 3.0]
        );
        assert_eq!(
            parse_box("0,0,0,1,2,3").unwrap(),
            [0.0, 0.0, 0.0, 1.0, 2.0, 3.0]
        );
        assert!(parse_box("1,2,3,4").is_err());
        assert!(parse_box("1,0").is_err());
        assert!(parse_box("x").is_err());
        let b = parse_box("0,0,0,1,2,4").unwrap();
        assert_eq!(parse_grid("4", &b).unwrap(), Resolution::CellSize(0.25));
        assert_eq!(
            parse_grid("1000", &b).unwrap(),
            Resolution::CellSize(1.0 / 250.0)
        );
        assert_eq!(parse_grid("2,4,8", &b).unwrap(), Resolution::CellSize(0.5));
    }

    #[test]
    fn detects_a_small_sphere() {
        let m = Model::compile(
            "my_model(x[3], a[1]) { my_model = 0.01 - ((x[1]-3)^2 + x[2]^2 + x[3]^2); }",
        )
        .unwrap();
        let b = detect(&m, &Inputs::default()).unwrap();
        assert!(
            b[0] < 2.9 && b[0] > 2.8 && b[3] > 3.1 && b[3] < 3.2,
            "{b:?}"
        );
        assert!(b[1] < -0.1 && b[1] > -0.2, "{b:?}");
        let half = Model::compile("my_model(x[3], a[1]) { my_model = x[1]; }").unwrap();
        assert_eq!(detect(&half, &Inputs::default()), None);
    }

    #[test]
    fn frames_a_noisy_offset_sphere_by_its_extent() {
        // A sphere of radius 3 at (5, 0, 0) with a noise term in the field. Its amplitude is
        // at most (1 + 1/1.17)^3 ≈ 6.4, so the solid reaches at most radius
        // sqrt(9 + 6.4) ≈ 3.93 from the centre.
        let src = "my_model(x[3], a[1]) {\n my_model = 9 - ((x[1]-5)^2 + x[2]^2 + x[3]^2)\n   + hfNoiseG(x, 1, 2, 0.5);\n}";
        let m = Model::compile(src).unwrap();
        let (b, origin) = model_box(src, &m, &Inputs::default());
        assert_eq!(origin, BoxOrigin::Extent);
        // Holds the sphere (the noise adds or takes away), hugs it within 20 %.
        assert!(b[0] <= 2.0 && b[0] > 0.2, "{b:?}");
        assert!(b[3] >= 8.0 && b[3] < 9.8, "{b:?}");
        for k in 1..3 {
            assert!(b[k] <= -3.0 && b[k] > -4.8, "{b:?}");
            assert!(b[k + 3] >= 3.0 && b[k + 3] < 4.8, "{b:?}");
        }
    }

    #[test]
    fn gives_up_quickly_where_intervals_prune_nothing() {
        // atan2 chains over powers (the corpus's broken exports): the interval
        // bounds are everywhere ambiguous, the budget runs out, no box.
        let src = "my_model(x[3], a[1]) { t = atan2(x[1]^x[2], max(x[3], 0.5)^x[1]);\n my_model = atan2(t, x[2]^x[3]) - 1; }";
        let m = Model::compile(src).unwrap();
        let (b, origin) = model_box(src, &m, &Inputs::default());
        assert_eq!((b, origin), (HFP_DEFAULT, BoxOrigin::Default));
        let with_line = format!("-- bounds: -1,-2,-3,1,2,3\n{src}");
        assert_eq!(
            model_box(&with_line, &m, &Inputs::default()),
            ([-1.0, -2.0, -3.0, 1.0, 2.0, 3.0], BoxOrigin::Comment)
        );
    }
}
