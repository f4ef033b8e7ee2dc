//! Sampling a field on a regular grid (slice by slice, batches of points) and
//! encoding it as a PNG stack and an 8-bit 3D texture with a JSON sidecar
//! ([`slice_files`]; the caller writes them).
//!
//! Field convention (HyperFun): positive inside, zero on the surface.
//! Byte mapping: byte `b` ↔ field value `v = (b − 128) / 127 × scale`.
//! - The surface is mid-grey 128, inside is bright and outside dark.
//! - Values beyond ±`scale` are clamped to 1 and 255.
//! - Byte 0 is kept for samples where the model failed (NaN), which read as
//!   outside.

use frep_core::CancelToken;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::camera::Aabb;
use crate::encode::{encode_png_gray, EncodeError};
use crate::files::OutFile;
use crate::raycast::RenderError;

/// Field samples on a regular grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Samples along x, y, z.
    pub n: [usize; 3],
    /// The box sampled; samples sit at voxel centres:
    /// `x_i = min + (i + 0.5) * (max − min) / n` (as a 3D texture's texels).
    pub bounds: Aabb,
    /// `nx * ny * nz` values, x fastest, then y, then z.
    pub values: Vec<f32>,
}

impl Grid {
    /// The world position of sample `(i, j, k)`.
    pub fn position(&self, i: usize, j: usize, k: usize) -> [f64; 3] {
        let idx = [i, j, k];
        std::array::from_fn(|a| {
            let (lo, hi) = (self.bounds.min[a], self.bounds.max[a]);
            lo + (idx[a] as f64 + 0.5) * (hi - lo) / self.n[a] as f64
        })
    }

    /// The value at sample `(i, j, k)`.
    pub fn get(&self, i: usize, j: usize, k: usize) -> f32 {
        self.values[(k * self.n[1] + j) * self.n[0] + i]
    }

    /// The size of one voxel along each axis.
    pub fn voxel_size(&self) -> [f64; 3] {
        std::array::from_fn(|a| (self.bounds.max[a] - self.bounds.min[a]) / self.n[a] as f64)
    }

    /// A scale for the byte mapping that resolves a band of about
    /// `band_voxels` voxels on each side of the surface: `band_voxels` times
    /// the median change of the field between neighbouring samples across the
    /// surface. Without any surface crossing, the largest finite |value|
    /// (or 1).
    pub fn auto_scale(&self, band_voxels: f32) -> f32 {
        let [nx, ny, nz] = self.n;
        let mut steps = Vec::new();
        let mut push = |a: f32, b: f32| {
            if a.is_finite() && b.is_finite() && (a > 0.0) != (b > 0.0) {
                steps.push((a - b).abs());
            }
        };
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let v = self.get(i, j, k);
                    if i + 1 < nx {
                        push(v, self.get(i + 1, j, k));
                    }
                    if j + 1 < ny {
                        push(v, self.get(i, j + 1, k));
                    }
                    if k + 1 < nz {
                        push(v, self.get(i, j, k + 1));
                    }
                }
            }
        }
        let s = if steps.is_empty() {
            self.values
                .iter()
                .filter(|v| v.is_finite())
                .fold(0.0f32, |m, v| m.max(v.abs()))
        } else {
            let mid = steps.len() / 2;
            let (_, m, _) = steps.select_nth_unstable_by(mid, f32::total_cmp);
            band_voxels.max(0.0) * *m
        };
        if s.is_finite() && s > 0.0 {
            s
        } else {
            1.0
        }
    }
}

/// Samples `f` at the voxel centres of an `n[0]×n[1]×n[2]` grid over
/// `bounds`. `f(xs, ys, zs, out)` evaluates a batch (one z slice,
/// `n[0] * n[1]` points, x fastest) and writes one value per point. Slices
/// run in parallel (rayon). Each row of `n[0]` points of a batch has one
/// `y` and one `z`, and every row the same `x`s (the same bits). So a batch
/// is a grid of lines along x, for
/// [`BatchEval::eval_lines`](frep_core::eval::batch::BatchEval::eval_lines)
/// `(0, n[0], true, ..)`. Once `cancel` is cancelled the slices left are
/// skipped and the result is [`RenderError::Cancelled`].
pub fn sample_grid<F>(
    bounds: &Aabb,
    n: [usize; 3],
    cancel: &CancelToken,
    f: F,
) -> Result<Grid, RenderError>
where
    F: Fn(&[f64], &[f64], &[f64], &mut [f64]) + Sync,
{
    let mut grid = Grid {
        n,
        bounds: *bounds,
        values: vec![0.0; n[0] * n[1] * n[2]],
    };
    let slice = n[0] * n[1];
    if slice == 0 || n[2] == 0 {
        return Ok(grid);
    }
    let coord = |a: usize, i: usize| {
        bounds.min[a] + (i as f64 + 0.5) * (bounds.max[a] - bounds.min[a]) / n[a] as f64
    };
    let xs_row: Vec<f64> = (0..n[0]).map(|i| coord(0, i)).collect();
    let mut xs = Vec::with_capacity(slice);
    let mut ys = Vec::with_capacity(slice);
    for j in 0..n[1] {
        xs.extend_from_slice(&xs_row);
        ys.extend(std::iter::repeat_n(coord(1, j), n[0]));
    }
    grid.values
        .par_chunks_mut(slice)
        .enumerate()
        .for_each(|(k, vals)| {
            if cancel.is_cancelled() {
                return;
            }
            let zs = vec![coord(2, k); slice];
            let mut out = vec![f64::NAN; slice];
            f(&xs, &ys, &zs, &mut out);
            for (d, s) in vals.iter_mut().zip(&out) {
                *d = *s as f32;
            }
        });
    if cancel.is_cancelled() {
        return Err(RenderError::Cancelled);
    }
    Ok(grid)
}

/// Field value to byte: `128 + 127 × v / scale`, rounded and clamped to
/// `1..=255`; NaN → 0.
pub fn field_to_byte(v: f32, scale: f32) -> u8 {
    if v.is_nan() {
        return 0;
    }
    (128.0 + 127.0 * v / scale).round().clamp(1.0, 255.0) as u8
}

/// Byte to field value: `(b − 128) / 127 × scale` (byte 0, the error byte,
/// reads as a little below −scale: outside).
pub fn byte_to_field(b: u8, scale: f32) -> f32 {
    (b as f32 - 128.0) / 127.0 * scale
}

/// What to write.
#[derive(Clone, Debug, PartialEq)]
pub struct SliceOptions {
    /// The byte mapping's scale; `None`: [`Grid::auto_scale`].
    pub scale: Option<f32>,
    /// Band half-width in voxels for the automatic scale.
    pub band_voxels: f32,
    /// Write one grey-scale PNG per z slice.
    pub pngs: bool,
    /// Write the raw 8-bit volume.
    pub raw: bool,
}

impl Default for SliceOptions {
    fn default() -> Self {
        SliceOptions {
            scale: None,
            band_voxels: 4.0,
            pngs: true,
            raw: true,
        }
    }
}

/// The byte ↔ field mapping, as recorded in the sidecar.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ByteMapping {
    /// The formula, for people reading the JSON.
    pub formula: String,
    /// The byte of the surface (field 0).
    pub zero_byte: u8,
    /// Bytes per `scale` of field value.
    pub bytes_per_scale: f32,
    /// The field value mapped to 255 (values beyond are clamped).
    pub scale: f32,
    /// Whether `scale` was chosen automatically.
    pub scale_auto: bool,
    /// The byte written where the model failed (NaN).
    pub error_byte: u8,
}

/// The JSON sidecar of a slice/volume export.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SliceIndex {
    /// Samples along x, y, z.
    pub dims: [usize; 3],
    /// The sampled box.
    pub bounds: Aabb,
    /// Voxel size along each axis.
    pub voxel_size: [f64; 3],
    /// Where samples sit.
    pub sample_positions: String,
    /// The byte mapping.
    pub mapping: ByteMapping,
    /// The raw volume's file, if written.
    pub raw: Option<String>,
    /// Layout of the raw volume.
    pub raw_layout: String,
    /// The PNG slice files, z ascending (empty if not written).
    pub pngs: Vec<String>,
    /// Orientation of the PNG slices.
    pub png_orientation: String,
    /// Smallest finite field value sampled.
    pub field_min: Option<f32>,
    /// Largest finite field value sampled.
    pub field_max: Option<f32>,
    /// Samples where the model failed (NaN).
    pub error_samples: usize,
}

/// The grid as bytes (x fastest, then y, then z) with the given scale.
pub fn grid_bytes(grid: &Grid, scale: f32) -> Vec<u8> {
    grid.values
        .iter()
        .map(|&v| field_to_byte(v, scale))
        .collect()
}

/// The files of `grid`: `slice_NNN.png` per z slice (8-bit grey, top row =
/// largest y), `volume.raw` (the 3D texture) and `volume.json` (the
/// sidecar, also returned), in that order. Slices are encoded in parallel.
pub fn slice_files(
    grid: &Grid,
    opts: &SliceOptions,
) -> Result<(SliceIndex, Vec<OutFile>), EncodeError> {
    let scale = opts
        .scale
        .filter(|s| s.is_finite() && *s > 0.0)
        .unwrap_or_else(|| grid.auto_scale(opts.band_voxels));
    let bytes = grid_bytes(grid, scale);
    let [nx, ny, nz] = grid.n;
    let digits = nz.saturating_sub(1).to_string().len().max(3);
    let pngs: Vec<String> = if opts.pngs {
        (0..nz).map(|k| format!("slice_{k:0digits$}.png")).collect()
    } else {
        Vec::new()
    };
    let mut files = Vec::new();
    if opts.pngs && nx * ny > 0 {
        files = (pngs.par_iter().enumerate())
            .map(|(k, name)| {
                let slice = &bytes[k * nx * ny..(k + 1) * nx * ny];
                let mut flipped = Vec::with_capacity(nx * ny);
                for j in (0..ny).rev() {
                    flipped.extend_from_slice(&slice[j * nx..(j + 1) * nx]);
                }
                let png = encode_png_gray(&flipped, nx as u32, ny as u32)?;
                Ok(OutFile::new(name, png))
            })
            .collect::<Result<_, EncodeError>>()?;
    }
    let raw = opts.raw.then(|| "volume.raw".to_string());
    if let Some(name) = &raw {
        files.push(OutFile::new(name, bytes));
    }
    let finite = grid.values.iter().copied().filter(|v| v.is_finite());
    let field_min = finite.clone().reduce(f32::min);
    let field_max = finite.reduce(f32::max);
    let index = SliceIndex {
        dims: grid.n,
        bounds: grid.bounds,
        voxel_size: grid.voxel_size(),
        sample_positions: "voxel centres: x_i = min + (i + 0.5) * (max - min) / n".into(),
        mapping: ByteMapping {
            formula: "v = (b - 128) / 127 * scale; b = 0 marks a model error (outside)".into(),
            zero_byte: 128,
            bytes_per_scale: 127.0,
            scale,
            scale_auto: opts.scale.is_none(),
            error_byte: 0,
        },
        raw,
        raw_layout: "u8 per voxel, x fastest, then y, then z".into(),
        pngs,
        png_orientation: "one PNG per z slice, z ascending; x to the right, top row = largest y"
            .into(),
        field_min,
        field_max,
        error_samples: grid.values.iter().filter(|v| v.is_nan()).count(),
    };
    let json =
        serde_json::to_string_pretty(&index).map_err(|e| EncodeError::Encoder(e.to_string()))?;
    files.push(OutFile::new("volume.json", json.into_bytes()));
    Ok((index, files))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HyperFun sphere, positive inside: r² − |p|².
    fn sphere(xs: &[f64], ys: &[f64], zs: &[f64], out: &mut [f64]) {
        for i in 0..out.len() {
            out[i] = 0.8 * 0.8 - (xs[i] * xs[i] + ys[i] * ys[i] + zs[i] * zs[i]);
        }
    }

    fn file<'a>(files: &'a [OutFile], name: &str) -> &'a [u8] {
        &files.iter().find(|f| f.name == name).unwrap().bytes
    }

    #[test]
    fn samples_at_voxel_centres() {
        let b = Aabb::new([0.0; 3], [1.0, 2.0, 4.0]);
        let g = sample_grid(&b, [2, 3, 4], &CancelToken::new(), |xs, ys, zs, out| {
            assert_eq!(xs.len(), 6);
            for i in 0..out.len() {
                out[i] = xs[i] + 10.0 * ys[i] + 100.0 * zs[i];
            }
        })
        .unwrap();
        assert_eq!(g.values.len(), 24);
        for (i, j, k) in [(0, 0, 0), (1, 2, 3), (1, 0, 2)] {
            let p = g.position(i, j, k);
            assert_eq!(g.get(i, j, k), (p[0] + 10.0 * p[1] + 100.0 * p[2]) as f32);
        }
        assert_eq!(g.position(0, 0, 0), [0.25, 1.0 / 3.0, 0.5]);
    }

    /// The batches are grids of lines along x (as documented, for
    /// `BatchEval::eval_lines`): per row one y and one z, every row the
    /// same xs, bit for bit.
    #[test]
    fn batches_are_grids_of_lines_along_x() {
        let b = Aabb::new([-0.3, 0.1, -2.0], [0.7, 2.0, 4.0]);
        let n = [5, 3, 4];
        sample_grid(&b, n, &CancelToken::new(), |xs, ys, zs, out| {
            assert_eq!(xs.len(), n[0] * n[1]);
            for (r, row) in xs.chunks(n[0]).enumerate() {
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(row), bits(&xs[..n[0]]), "row {r}: xs");
                for i in r * n[0]..(r + 1) * n[0] {
                    assert_eq!(ys[i].to_bits(), ys[r * n[0]].to_bits(), "row {r}: ys");
                    assert_eq!(zs[i].to_bits(), zs[r * n[0]].to_bits(), "row {r}: zs");
                }
            }
            out.fill(0.0);
        })
        .unwrap();
    }

    #[test]
    fn a_cancelled_grid_samples_nothing() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cancel = CancelToken::new();
        cancel.cancel();
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let r = sample_grid(&b, [4, 4, 4], &cancel, |_, _, _, out| {
            calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            out.fill(1.0);
        });
        assert_eq!(r, Err(RenderError::Cancelled));
        assert_eq!(calls.into_inner(), 0);
    }

    #[test]
    fn mapping_round_trips() {
        let scale = 0.37;
        let step = scale / 127.0;
        for i in -200..=200 {
            let v = i as f32 / 200.0 * scale;
            let b = field_to_byte(v, scale);
            assert!(
                (byte_to_field(b, scale) - v).abs() <= 0.5 * step + 1e-6,
                "{v}"
            );
        }
        assert_eq!(field_to_byte(0.0, scale), 128);
        assert_eq!(field_to_byte(10.0, scale), 255);
        assert_eq!(field_to_byte(-10.0, scale), 1);
        assert_eq!(field_to_byte(f32::NAN, scale), 0);
        assert_eq!(field_to_byte(f32::INFINITY, scale), 255);
    }

    #[test]
    fn auto_scale_resolves_the_band() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let g = sample_grid(&b, [32, 32, 32], &CancelToken::new(), sphere).unwrap();
        let s = g.auto_scale(4.0);
        // |∇f| = 2r = 1.6 at the surface, voxel 1/16: a step is ~0.1.
        assert!(s > 0.25 && s < 0.6, "{s}");
        let none = sample_grid(&b, [4, 4, 4], &CancelToken::new(), |_, _, _, out| {
            out.fill(-3.0)
        })
        .unwrap();
        assert_eq!(none.auto_scale(4.0), 3.0);
    }

    #[test]
    fn sphere_slices_and_volume() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let n = [20, 16, 12];
        let mut g = sample_grid(&b, n, &CancelToken::new(), sphere).unwrap();
        g.values[0] = f32::NAN;
        let (idx, files) = slice_files(&g, &SliceOptions::default()).unwrap();
        assert_eq!(idx.pngs.len(), 12);
        assert_eq!(files.len(), 12 + 2);
        assert_eq!(idx.error_samples, 1);
        let raw = file(&files, "volume.raw");
        assert_eq!(raw.len(), 20 * 16 * 12);
        assert_eq!(raw[0], 0);
        // Middle slice: centre bright, corner dark.
        let png = file(&files, &idx.pngs[6]);
        let mut r = png::Decoder::new(std::io::Cursor::new(png))
            .read_info()
            .unwrap();
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        let info = r.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (20, 16));
        assert_eq!(info.color_type, png::ColorType::Grayscale);
        assert!(buf[8 * 20 + 10] > 200, "{}", buf[8 * 20 + 10]);
        assert!(buf[0] < 60);
        // The PNG is the raw slice flipped vertically.
        let k = 6 * 20 * 16;
        assert_eq!(&buf[15 * 20..16 * 20], &raw[k..k + 20]);
        // The sidecar.
        let json: SliceIndex = serde_json::from_slice(file(&files, "volume.json")).unwrap();
        assert_eq!(json, idx);
        assert_eq!(json.dims, n);
        assert!(json.mapping.scale_auto);
        // Decoding a byte gives the sampled value within a quantization step
        // where the value is inside the band.
        let s = json.mapping.scale;
        for (v, b) in g.values.iter().zip(raw).skip(1) {
            if v.abs() <= s {
                assert!((byte_to_field(*b, s) - v).abs() <= 0.5 * s / 127.0 + 1e-6);
            }
        }
    }

    #[test]
    fn given_scale_and_no_pngs() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let g = sample_grid(&b, [4, 4, 4], &CancelToken::new(), sphere).unwrap();
        let opts = SliceOptions {
            scale: Some(2.0),
            pngs: false,
            ..Default::default()
        };
        let (idx, files) = slice_files(&g, &opts).unwrap();
        assert!(idx.pngs.is_empty());
        assert_eq!(idx.mapping.scale, 2.0);
        assert!(!idx.mapping.scale_auto);
        let names: Vec<&str> = files.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, ["volume.raw", "volume.json"]);
    }
}
