//! Progressive delivery: a plan of coarse-to-fine frames (render a reduced
//! image, show it upscaled, then render the full frame), and the upscaler.

use crate::image::Image;

/// One frame of a progressive plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ProgressiveStep {
    /// The reduction factor: the frame is rendered at `1/factor` resolution.
    pub factor: u32,
    /// Width to render at (`ceil(full width / factor)`).
    pub width: u32,
    /// Height to render at (`ceil(full height / factor)`).
    pub height: u32,
}

/// Coarse-to-fine frames for a `width`×`height` view, the last one always
/// the full resolution.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProgressivePlan {
    /// Full width.
    pub width: u32,
    /// Full height.
    pub height: u32,
    /// The frames in order, coarsest first, ending with factor 1.
    pub steps: Vec<ProgressiveStep>,
}

impl ProgressivePlan {
    /// A plan with the given reduction factors (each > 1, coarsest first;
    /// others are dropped) followed by the full frame. E.g. `&[4]`: a
    /// quarter-resolution frame, then the full one.
    pub fn new(width: u32, height: u32, factors: &[u32]) -> ProgressivePlan {
        let mut steps = Vec::new();
        let mut last = u32::MAX;
        for &f in factors {
            if f > 1 && f < last {
                steps.push(Self::step(width, height, f));
                last = f;
            }
        }
        steps.push(Self::step(width, height, 1));
        ProgressivePlan {
            width,
            height,
            steps,
        }
    }

    /// The usual plan: quarter resolution, then full.
    pub fn quarter_then_full(width: u32, height: u32) -> ProgressivePlan {
        Self::new(width, height, &[4])
    }

    fn step(width: u32, height: u32, factor: u32) -> ProgressiveStep {
        ProgressiveStep {
            factor,
            width: width.div_ceil(factor).max(1),
            height: height.div_ceil(factor).max(1),
        }
    }

    /// Brings the frame rendered for `step` to full size: upscaled by the
    /// step's factor (nearest neighbour) and cropped to the full size.
    pub fn to_full(&self, step: &ProgressiveStep, frame: &Image) -> Image {
        let up = upscale_nearest(frame, step.factor);
        crop(&up, self.width, self.height)
    }
}

/// Each pixel becomes a `factor`×`factor` block.
pub fn upscale_nearest(img: &Image, factor: u32) -> Image {
    let f = factor.max(1);
    let (w, h) = (img.width * f, img.height * f);
    let mut rgba = Vec::with_capacity(w as usize * h as usize * 4);
    for y in 0..h {
        let src = &img.rgba[(y / f) as usize * img.width as usize * 4..][..img.width as usize * 4];
        for p in src.chunks_exact(4) {
            for _ in 0..f {
                rgba.extend_from_slice(p);
            }
        }
    }
    Image {
        width: w,
        height: h,
        rgba,
    }
}

/// The top-left `width`×`height` part of `img` (clipped to its size).
pub fn crop(img: &Image, width: u32, height: u32) -> Image {
    let (w, h) = (width.min(img.width), height.min(img.height));
    let mut out = Image::filled(w, h, [0; 4]);
    for y in 0..h {
        let s = y as usize * img.width as usize * 4;
        let d = y as usize * w as usize * 4;
        out.rgba[d..d + w as usize * 4].copy_from_slice(&img.rgba[s..s + w as usize * 4]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_steps() {
        let p = ProgressivePlan::quarter_then_full(513, 256);
        assert_eq!(p.steps.len(), 2);
        assert_eq!(
            p.steps[0],
            ProgressiveStep {
                factor: 4,
                width: 129,
                height: 64
            }
        );
        assert_eq!(p.steps[1].factor, 1);
        assert_eq!((p.steps[1].width, p.steps[1].height), (513, 256));
        let p = ProgressivePlan::new(100, 100, &[8, 2, 4, 1, 0]);
        let f: Vec<u32> = p.steps.iter().map(|s| s.factor).collect();
        assert_eq!(f, vec![8, 2, 1]);
    }

    #[test]
    fn upscale_and_crop() {
        let mut img = Image::filled(2, 2, [0, 0, 0, 255]);
        img.set_pixel(1, 0, [255, 0, 0, 255]);
        let up = upscale_nearest(&img, 3);
        assert_eq!((up.width, up.height), (6, 6));
        assert_eq!(up.pixel(3, 0), [255, 0, 0, 255]);
        assert_eq!(up.pixel(5, 2), [255, 0, 0, 255]);
        assert_eq!(up.pixel(2, 2), [0, 0, 0, 255]);
        assert_eq!(up.pixel(5, 3), [0, 0, 0, 255]);
        let p = ProgressivePlan::new(5, 4, &[3]);
        let full = p.to_full(&p.steps[0], &img);
        assert_eq!((full.width, full.height), (5, 4));
        assert_eq!(full.pixel(4, 1), [255, 0, 0, 255]);
        assert_eq!(upscale_nearest(&img, 1), img);
    }
}
