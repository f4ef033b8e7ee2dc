//! View sets: a turntable of views around a model (optionally on several
//! elevation rings), rendered in parallel, encoded as separate images plus
//! one sprite sheet and a JSON index ([`view_set_files`]; the caller writes
//! them).

use frep_core::CancelToken;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::camera::{Aabb, Camera, Projection};
use crate::encode::{encode, EncodeError, ImageFormat};
use crate::files::OutFile;
use crate::image::Image;
use crate::raycast::RenderError;

/// What to render.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewSetOptions {
    /// Views per ring, evenly spaced in yaw.
    pub views: u32,
    /// Pitch of each ring in degrees (one ring per entry); empty means one
    /// ring at pitch 0.
    pub elevations: Vec<f64>,
    /// Size of each view in pixels `(width, height)`.
    pub size: (u32, u32),
    /// Image format of the views and the sheet.
    pub format: ImageFormat,
    /// Encoder quality 1–100 (JPEG, WebP).
    pub quality: u8,
    /// Field of view in degrees for perspective views; `None`: orthographic.
    pub fov_deg: Option<f64>,
    /// Yaw of the first view in degrees.
    pub start_yaw: f64,
    /// Columns of the sprite sheet; `None`: one row per ring when that fits
    /// in 16 383 pixels (the WebP limit), otherwise a near-square grid.
    pub sheet_columns: Option<u32>,
}

impl Default for ViewSetOptions {
    fn default() -> Self {
        ViewSetOptions {
            views: 12,
            elevations: vec![20.0],
            size: (256, 256),
            format: ImageFormat::Jpeg,
            quality: 75,
            fov_deg: Some(30.0),
            start_yaw: 0.0,
            sheet_columns: None,
        }
    }
}

/// A rectangle in the sprite sheet, in pixels from the top-left.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rect {
    /// Left edge.
    pub x: u32,
    /// Top edge.
    pub y: u32,
    /// Width.
    pub w: u32,
    /// Height.
    pub h: u32,
}

/// A camera as recorded in the index.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraInfo {
    /// Eye position.
    pub eye: [f64; 3],
    /// Point looked at.
    pub target: [f64; 3],
    /// Up direction of the image.
    pub up: [f64; 3],
    /// The projection (perspective `fov_deg` or orthographic `half_extent`,
    /// both across the shorter image side).
    pub projection: Projection,
}

impl From<&Camera> for CameraInfo {
    fn from(c: &Camera) -> Self {
        CameraInfo {
            eye: c.eye,
            target: c.target,
            up: c.up,
            projection: c.projection,
        }
    }
}

/// One view in the index.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewInfo {
    /// Index in the set (ring-major: ring 0's views first).
    pub index: u32,
    /// Which elevation ring.
    pub ring: u32,
    /// Yaw in degrees.
    pub yaw: f64,
    /// Pitch in degrees.
    pub pitch: f64,
    /// The file of this view, relative to the index.
    pub file: String,
    /// The camera.
    pub camera: CameraInfo,
    /// Where this view lies in the sprite sheet.
    pub rect: Rect,
}

/// The sprite sheet in the index.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SheetInfo {
    /// The sheet's file, relative to the index.
    pub file: String,
    /// Sheet width in pixels.
    pub width: u32,
    /// Sheet height in pixels.
    pub height: u32,
    /// Grid columns.
    pub columns: u32,
    /// Grid rows.
    pub rows: u32,
}

/// The JSON index of a view set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewSetIndex {
    /// Image format of all files.
    pub format: ImageFormat,
    /// Encoder quality.
    pub quality: u8,
    /// View size `[width, height]`.
    pub view_size: [u32; 2],
    /// Views per ring.
    pub views_per_ring: u32,
    /// Pitch of each ring in degrees.
    pub elevations: Vec<f64>,
    /// The model bounds the cameras frame.
    pub bounds: Aabb,
    /// The sprite sheet.
    pub sheet: SheetInfo,
    /// Every view, ring-major.
    pub views: Vec<ViewInfo>,
}

/// A rendered view set, in memory.
#[derive(Clone, Debug)]
pub struct ViewSet {
    /// The index (file names are those of [`view_set_files`]).
    pub index: ViewSetIndex,
    /// The views, in index order.
    pub images: Vec<Image>,
    /// All views on one sheet.
    pub sheet: Image,
}

impl ViewSet {
    /// The same views to be written in another format and quality (file
    /// names in the index follow the format).
    pub fn with_format(mut self, format: ImageFormat, quality: u8) -> ViewSet {
        let ext = format.extension();
        self.index.format = format;
        self.index.quality = quality;
        self.index.sheet.file = format!("sheet.{ext}");
        for v in &mut self.index.views {
            v.file = format!("view_{:03}.{ext}", v.index);
        }
        self
    }
}

/// The cameras of a view set: for each ring (pitch) and view (yaw), ring-major.
pub fn view_cameras(bounds: &Aabb, opts: &ViewSetOptions) -> Vec<(u32, f64, f64, Camera)> {
    let rings: Vec<f64> = if opts.elevations.is_empty() {
        vec![0.0]
    } else {
        opts.elevations.clone()
    };
    let n = opts.views.max(1);
    let mut out = Vec::new();
    for (ring, &pitch) in rings.iter().enumerate() {
        for v in 0..n {
            let yaw = opts.start_yaw + 360.0 * v as f64 / n as f64;
            out.push((
                ring as u32,
                yaw,
                pitch,
                Camera::orbit(bounds, yaw, pitch, opts.fov_deg),
            ));
        }
    }
    out
}

fn sheet_grid(opts: &ViewSetOptions, count: u32) -> (u32, u32) {
    let per_ring = opts.views.max(1);
    let cols = match opts.sheet_columns {
        Some(c) => c.clamp(1, count.max(1)),
        None if per_ring * opts.size.0 <= 16_383 => per_ring,
        None => (count as f64).sqrt().ceil() as u32,
    };
    (cols, count.div_ceil(cols))
}

/// Renders every view with `render(camera, width, height)` (in parallel
/// across views) and lays them out on a sprite sheet. A rendered image of the
/// wrong size is cropped or padded (transparent) to the view size. Once
/// `cancel` is cancelled the views left are not rendered and the result is
/// [`RenderError::Cancelled`].
pub fn render_view_set<R>(
    bounds: &Aabb,
    opts: &ViewSetOptions,
    cancel: &CancelToken,
    render: R,
) -> Result<ViewSet, RenderError>
where
    R: Fn(&Camera, u32, u32) -> Image + Sync,
{
    let (w, h) = opts.size;
    let cams = view_cameras(bounds, opts);
    let images: Vec<Image> = cams
        .par_iter()
        .map(|(_, _, _, cam)| {
            if cancel.is_cancelled() {
                return Image::filled(w, h, [0; 4]);
            }
            let img = render(cam, w, h);
            if img.width == w && img.height == h {
                img
            } else {
                let mut fixed = Image::filled(w, h, [0; 4]);
                fixed.blit(&img, 0, 0);
                fixed
            }
        })
        .collect();
    if cancel.is_cancelled() {
        return Err(RenderError::Cancelled);
    }
    let (cols, rows) = sheet_grid(opts, cams.len() as u32);
    let mut sheet = Image::filled(cols * w, rows * h, [0, 0, 0, 255]);
    let ext = opts.format.extension();
    let mut views = Vec::with_capacity(cams.len());
    for (i, ((ring, yaw, pitch, cam), img)) in cams.iter().zip(&images).enumerate() {
        let i = i as u32;
        let rect = Rect {
            x: (i % cols) * w,
            y: (i / cols) * h,
            w,
            h,
        };
        sheet.blit(img, rect.x, rect.y);
        views.push(ViewInfo {
            index: i,
            ring: *ring,
            yaw: *yaw,
            pitch: *pitch,
            file: format!("view_{i:03}.{ext}"),
            camera: CameraInfo::from(cam),
            rect,
        });
    }
    let index = ViewSetIndex {
        format: opts.format,
        quality: opts.quality,
        view_size: [w, h],
        views_per_ring: opts.views.max(1),
        elevations: if opts.elevations.is_empty() {
            vec![0.0]
        } else {
            opts.elevations.clone()
        },
        bounds: *bounds,
        sheet: SheetInfo {
            file: format!("sheet.{ext}"),
            width: sheet.width,
            height: sheet.height,
            columns: cols,
            rows,
        },
        views,
    };
    Ok(ViewSet {
        index,
        images,
        sheet,
    })
}

/// The files of a view set: `view_NNN.ext` for each view, `sheet.ext`,
/// and `index.json`, in that order. Views are encoded in parallel.
pub fn view_set_files(set: &ViewSet) -> Result<Vec<OutFile>, EncodeError> {
    let (format, quality) = (set.index.format, set.index.quality);
    let mut files: Vec<OutFile> = (set.images.par_iter())
        .zip(&set.index.views)
        .map(|(img, v)| Ok(OutFile::new(&v.file, encode(img, format, quality)?)))
        .collect::<Result<_, EncodeError>>()?;
    let sheet = encode(&set.sheet, format, quality)?;
    files.push(OutFile::new(&set.index.sheet.file, sheet));
    let json = serde_json::to_string_pretty(&set.index)
        .map_err(|e| EncodeError::Encoder(e.to_string()))?;
    files.push(OutFile::new("index.json", json.into_bytes()));
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{shade, Lighting};
    use crate::synthetic::sphere_hits;

    fn sphere_renderer(cam: &Camera, w: u32, h: u32) -> Image {
        // An off-centre sphere so views differ.
        shade(
            &sphere_hits(cam, w, h, [0.5, 0.0, 0.0], 0.4, Some([0.9, 0.5, 0.2])),
            &Lighting::default(),
        )
    }

    #[test]
    fn cameras_go_around() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let opts = ViewSetOptions {
            views: 4,
            elevations: vec![0.0, 45.0],
            ..Default::default()
        };
        let cams = view_cameras(&b, &opts);
        assert_eq!(cams.len(), 8);
        assert_eq!(cams[1].1, 90.0);
        assert_eq!(cams[5].0, 1);
        assert_eq!(cams[5].2, 45.0);
        // Opposite views look in opposite directions.
        let (f0, f2) = (cams[0].3.forward, cams[2].3.forward);
        assert!((f0[1] + f2[1]).abs() < 1e-12 && f0[1] > 0.9);
    }

    #[test]
    fn view_set_files_and_index() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let opts = ViewSetOptions {
            views: 6,
            elevations: vec![0.0, 30.0],
            size: (48, 32),
            format: ImageFormat::Png,
            ..Default::default()
        };
        let set = render_view_set(&b, &opts, &CancelToken::new(), sphere_renderer).unwrap();
        assert_eq!(set.images.len(), 12);
        assert_eq!((set.sheet.width, set.sheet.height), (6 * 48, 2 * 32));
        // View 0 and view 3 (half a turn apart) see the sphere on opposite sides.
        assert_ne!(set.images[0], set.images[3]);
        // The sheet holds each view at its rect.
        let v = &set.index.views[7];
        assert_eq!((v.rect.x, v.rect.y), (48, 32));
        assert_eq!(
            set.sheet.pixel(v.rect.x + 20, v.rect.y + 10),
            set.images[7].pixel(20, 10)
        );

        let files = view_set_files(&set).unwrap();
        let file = |name: &str| &files.iter().find(|f| f.name == name).unwrap().bytes;
        let jpeg = set.clone().with_format(ImageFormat::Jpeg, 80);
        assert_eq!(jpeg.index.views[3].file, "view_003.jpg");
        assert_eq!(jpeg.index.sheet.file, "sheet.jpg");
        assert_eq!(jpeg.index.quality, 80);
        assert_eq!(files.len(), 12 + 2);
        let json = String::from_utf8(file("index.json").clone()).unwrap();
        let back: ViewSetIndex = serde_json::from_str(&json).unwrap();
        // (serde_json's default float parsing may differ in the last bit.)
        assert_eq!(back.sheet, set.index.sheet);
        for (a, b) in back.views.iter().zip(&set.index.views) {
            assert_eq!(
                (a.index, a.ring, &a.file, a.rect),
                (b.index, b.ring, &b.file, b.rect)
            );
            for k in 0..3 {
                assert!((a.camera.eye[k] - b.camera.eye[k]).abs() < 1e-12);
                assert!((a.camera.up[k] - b.camera.up[k]).abs() < 1e-12);
            }
        }
        let value: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(
            value["views"][1]["camera"]["projection"]["kind"],
            "perspective"
        );
        assert_eq!(value["views"][1]["rect"]["x"], 48);
        assert_eq!(value["format"], "png");
        for (v, f) in back.views.iter().zip(&files) {
            assert_eq!(v.file, f.name);
        }
        let sheet = file("sheet.png").clone();
        let r = png::Decoder::new(std::io::Cursor::new(sheet))
            .read_info()
            .unwrap();
        assert_eq!((r.info().width, r.info().height), (288, 64));
    }

    #[test]
    fn wide_sets_wrap_and_sizes_are_fixed() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let opts = ViewSetOptions {
            views: 36,
            elevations: vec![],
            size: (512, 8),
            fov_deg: None,
            ..Default::default()
        };
        // The renderer returns a wrong size: it is padded.
        let cancel = CancelToken::new();
        let set = render_view_set(&b, &opts, &cancel, |_, _, _| {
            Image::filled(3, 3, [1, 2, 3, 255])
        })
        .unwrap();
        assert_eq!(set.index.sheet.columns, 6);
        assert_eq!(set.index.sheet.rows, 6);
        assert_eq!(set.images[0].width, 512);
        assert_eq!(set.images[0].pixel(100, 0), [0; 4]);
        assert_eq!(set.index.elevations, vec![0.0]);
        assert!(matches!(
            set.index.views[0].camera.projection,
            Projection::Orthographic { .. }
        ));
        // Cancelled after the first view: no more renders, and an error.
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let r = render_view_set(&b, &opts, &cancel, |_, w, h| {
            calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            cancel.cancel();
            Image::filled(w, h, [0; 4])
        });
        assert_eq!(r.err(), Some(RenderError::Cancelled));
        // (Views already started on other threads may finish.)
        assert!(calls.into_inner() <= rayon::current_num_threads());
    }
}
