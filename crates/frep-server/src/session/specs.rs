//! The artefacts a delivery mode needs, by role, within the server's limits:
//! - `image`: mode 1's first display;
//! - `viewSetIndex` + `viewSet`: mode 2;
//! - `meshCoarse` + `mesh`: mode 3;
//! - `shader`: mode 4a;
//! - `slices`: volume;
//! - none for mode 4b: the browser polygonizes the source it has.
//!
//! The engine does not know the server's limits, so each spec is brought
//! within them. Sizes are scaled down with their aspect; views, depths and
//! grids are capped.

use frep_artefact::ArtefactLimits;
use frep_wire::{ArtefactSpec, CameraView, Decision, Mode, SectionPlane};

/// The artefacts a mode needs, by role (module docs); the images and view
/// sets cut by the client's section plane, if any.
pub fn specs(
    decision: &Decision,
    camera: &CameraView,
    section: Option<SectionPlane>,
) -> Vec<(&'static str, ArtefactSpec)> {
    let s = &decision.settings;
    match decision.mode {
        Mode::Still => vec![(
            "image",
            ArtefactSpec::Image {
                camera: camera.clone(),
                width: s.width,
                height: s.height,
                format: s.format,
                quality: s.quality,
                section,
            },
        )],
        Mode::ViewSet => {
            let (views, elevations) = (s.views, s.elevations.clone());
            let (width, height, format, quality) = (s.width, s.height, s.format, s.quality);
            let fov = camera.fov;
            vec![
                (
                    "viewSetIndex",
                    ArtefactSpec::ViewSetIndex {
                        views,
                        elevations: elevations.clone(),
                        width,
                        height,
                        format,
                        quality,
                        fov,
                        section,
                    },
                ),
                (
                    "viewSet",
                    ArtefactSpec::ViewSet {
                        views,
                        elevations,
                        width,
                        height,
                        format,
                        quality,
                        fov,
                        section,
                    },
                ),
            ]
        }
        Mode::ServerMesh => {
            let mut v = Vec::new();
            if s.coarse_depth > 0 && s.coarse_depth < s.mesh_depth {
                v.push((
                    "meshCoarse",
                    ArtefactSpec::Mesh {
                        depth: s.coarse_depth,
                    },
                ));
            }
            v.push((
                "mesh",
                ArtefactSpec::Mesh {
                    depth: s.mesh_depth,
                },
            ));
            v
        }
        Mode::GpuRaycast => vec![("shader", ArtefactSpec::Shader)],
        Mode::Volume => vec![(
            "slices",
            ArtefactSpec::Slices {
                grid: s.volume_grid,
            },
        )],
        // The browser polygonizes from the source it already has.
        Mode::WasmMesh => Vec::new(),
    }
}

/// `(width, height)` scaled down (aspect kept) to at most `max_side` and
/// `max_pixels`.
fn fit_size(width: u32, height: u32, max_side: u32, max_pixels: u64) -> (u32, u32) {
    let (w, h) = (f64::from(width.max(1)), f64::from(height.max(1)));
    let mut scale = (f64::from(max_side.max(1)) / w.max(h)).min(1.0);
    let px = w * h * scale * scale;
    if px > max_pixels.max(1) as f64 {
        scale *= (max_pixels.max(1) as f64 / px).sqrt();
    }
    let side = |v: f64| ((v * scale).floor() as u32).max(1);
    (side(w), side(h))
}

/// A spec brought within the server's limits: the engine does not know
/// them, and a decision must never ask for what the service refuses.
pub fn fit(spec: ArtefactSpec, limits: &ArtefactLimits) -> ArtefactSpec {
    let (side, pixels) = (limits.max_image_side, limits.max_image_pixels);
    match spec {
        ArtefactSpec::Image {
            camera,
            width,
            height,
            format,
            quality,
            section,
        } => {
            let (width, height) = fit_size(width, height, side, pixels);
            ArtefactSpec::Image {
                camera,
                width,
                height,
                format,
                quality,
                section,
            }
        }
        ArtefactSpec::ViewSet {
            views,
            elevations,
            width,
            height,
            format,
            quality,
            fov,
            section,
        } => {
            let (views, width, height) = fit_views(views, &elevations, width, height, limits);
            ArtefactSpec::ViewSet {
                views,
                elevations,
                width,
                height,
                format,
                quality,
                fov,
                section,
            }
        }
        ArtefactSpec::ViewSetIndex {
            views,
            elevations,
            width,
            height,
            format,
            quality,
            fov,
            section,
        } => {
            let (views, width, height) = fit_views(views, &elevations, width, height, limits);
            ArtefactSpec::ViewSetIndex {
                views,
                elevations,
                width,
                height,
                format,
                quality,
                fov,
                section,
            }
        }
        ArtefactSpec::Mesh { depth } => ArtefactSpec::Mesh {
            depth: depth.min(limits.max_mesh_depth),
        },
        ArtefactSpec::Slices { grid } => ArtefactSpec::Slices {
            grid: grid.min(limits.max_volume_grid),
        },
        other => other,
    }
}

/// Views per ring and view size within the view and sheet limits.
fn fit_views(
    views: u32,
    elevations: &[f64],
    width: u32,
    height: u32,
    limits: &ArtefactLimits,
) -> (u32, u32, u32) {
    let rings = elevations.len().max(1) as u32;
    let views = views.clamp(1, (limits.max_views / rings).max(1));
    let count = u64::from(views) * u64::from(rings);
    // Each view gets its share of the sheet's pixels.
    let share = limits.max_sheet_pixels / count.max(1);
    let (w, h) = fit_size(
        width,
        height,
        limits.max_image_side,
        limits.max_image_pixels.min(share),
    );
    (views, w, h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use frep_wire::ImageEncoding;

    #[test]
    fn specs_are_fitted_to_the_limits() {
        let limits = ArtefactLimits {
            max_image_side: 1000,
            max_image_pixels: 200_000,
            max_views: 24,
            max_sheet_pixels: 2_400_000,
            max_mesh_depth: 7,
            max_volume_grid: 64,
            ..ArtefactLimits::default()
        };
        let image = ArtefactSpec::Image {
            camera: CameraView::default(),
            width: 2000,
            height: 1000,
            format: ImageEncoding::Jpeg,
            quality: 80,
            section: None,
        };
        let ArtefactSpec::Image { width, height, .. } = fit(image, &limits) else {
            panic!()
        };
        assert!(width <= 1000 && u64::from(width * height) <= 200_000);
        assert!((f64::from(width) / f64::from(height) - 2.0).abs() < 0.01);
        let set = ArtefactSpec::ViewSet {
            views: 36,
            elevations: vec![0.0, 30.0],
            width: 512,
            height: 512,
            format: ImageEncoding::Jpeg,
            quality: 75,
            fov: None,
            section: None,
        };
        let ArtefactSpec::ViewSet { views, width, .. } = fit(set, &limits) else {
            panic!()
        };
        assert_eq!(views, 12);
        assert!(u64::from(width * width) * 24 <= 2_400_000);
        assert_eq!(
            fit(ArtefactSpec::Mesh { depth: 9 }, &limits),
            ArtefactSpec::Mesh { depth: 7 }
        );
        assert_eq!(
            fit(ArtefactSpec::Slices { grid: 128 }, &limits),
            ArtefactSpec::Slices { grid: 64 }
        );
    }

    /// A decision in `mode` with small settings, for the tests.
    fn decision(mode: Mode) -> Decision {
        Decision {
            mode,
            settings: frep_wire::ModeSettings {
                width: 100,
                height: 100,
                quality: 80,
                moving_scale: 2.0,
                moving_quality: 50,
                format: ImageEncoding::Jpeg,
                views: 12,
                elevations: vec![0.0],
                mesh_depth: 6,
                coarse_depth: 4,
                volume_grid: 64,
            },
            reason: String::new(),
            overridden: false,
            predictions: vec![],
            network: frep_wire::NetworkEstimate {
                rtt_ms: 1.0,
                bandwidth_bps: 1e6,
                samples: 0,
            },
            trigger: "connect".into(),
            seq: 1,
        }
    }

    /// The client's section plane goes into the images and view sets a
    /// mode needs, and stays through the fit to the limits.
    #[test]
    fn specs_carry_the_section() {
        let mut d = decision(Mode::Still);
        let cut = Some(SectionPlane {
            normal: [1.0, 0.0, 0.0],
            offset: 0.2,
        });
        for mode in [Mode::Still, Mode::ViewSet] {
            d.mode = mode;
            let got = specs(&d, &CameraView::default(), cut);
            assert!(!got.is_empty());
            for (role, spec) in got {
                let spec = fit(spec, &ArtefactLimits::default());
                let section = match spec {
                    ArtefactSpec::Image { section, .. }
                    | ArtefactSpec::ViewSet { section, .. }
                    | ArtefactSpec::ViewSetIndex { section, .. } => section,
                    _ => panic!("{role}"),
                };
                assert_eq!(section, cut, "{role}");
            }
        }
    }

    #[test]
    fn a_mode_asks_for_its_roles() {
        let roles = |m| -> Vec<&str> {
            specs(&decision(m), &CameraView::default(), None)
                .into_iter()
                .map(|(r, _)| r)
                .collect()
        };
        assert_eq!(roles(Mode::Still), ["image"]);
        assert_eq!(roles(Mode::ViewSet), ["viewSetIndex", "viewSet"]);
        assert_eq!(roles(Mode::ServerMesh), ["meshCoarse", "mesh"]);
        assert_eq!(roles(Mode::GpuRaycast), ["shader"]);
        assert_eq!(roles(Mode::Volume), ["slices"]);
        assert!(roles(Mode::WasmMesh).is_empty());
    }
}
