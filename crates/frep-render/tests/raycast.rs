//! Tests of the FRep ray caster on real models: golden masks kept as text
//! (`FREP_BLESS=1` rewrites them), thin slabs, a grazing view of the gyroid
//! against a dense fixed-step reference, scaled fields, a field with zero
//! gradient on its surface, cancellation, attribute colours, a pruning
//! regression bound, hits on the surface to a fraction of a footprint,
//! solids cut open by the model box hit at their first crossing (depths
//! against a dense reference), and rays down a tube's bore dropped after one
//! interval check, with the same hits; tiles around a small model found
//! empty whole, before their rays are set up.

use frep_core::eval::batch::{BatchEval, Trig};
use frep_core::eval::grad::GradEval;
use frep_core::eval::Inputs;
use frep_core::{Model, PointEval};
use frep_render::{
    ascii_mask, cast_tiled, render, render_hits, shade, Aabb, Camera, CancelToken, CastStats,
    HitBuffer, ImagePool, ModelCaster, RenderError, RenderLimits, RenderSettings,
};

fn example(name: &str) -> String {
    let p = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{p}: {e}"))
}

/// The `-- bounds: x0,y0,z0,x1,y1,z1` line of an example.
fn bounds_of(src: &str) -> Aabb {
    let line = src
        .lines()
        .find_map(|l| l.trim().strip_prefix("-- bounds:"))
        .expect("bounds line");
    let v: Vec<f64> = line.split(',').map(|s| s.trim().parse().unwrap()).collect();
    Aabb::new([v[0], v[1], v[2]], [v[3], v[4], v[5]])
}

/// A pool of `threads` rayon threads.
fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

fn settings(bounds: Aabb, w: u32, h: u32) -> RenderSettings {
    RenderSettings {
        size: (w, h),
        bounds,
        tile_size: 16,
        ..Default::default()
    }
}

fn mask(h: &HitBuffer) -> Vec<bool> {
    h.hits.iter().map(|h| h.is_some()).collect()
}

fn check_golden(name: &str, got: &str) {
    let path = format!("{}/tests/golden/{name}.txt", env!("CARGO_MANIFEST_DIR"));
    if std::env::var_os("FREP_BLESS").is_some() {
        std::fs::write(&path, got).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{path}: {e} (run with FREP_BLESS=1 to create it)"));
    assert_eq!(got, want, "golden mask {name} differs:\n{got}");
}

fn golden(file: &str, name: &str) {
    let src = example(file);
    let model = Model::compile(&src).unwrap();
    let s = settings(bounds_of(&src), 80, 80);
    let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
    check_golden(name, &ascii_mask(&hits, 40, 20));
}

#[test]
fn golden_m1() {
    golden("m1_sphere.hf", "m1_sphere");
}

#[test]
fn golden_m4() {
    golden("m4_rblend10.hf", "m4_rblend10");
}

#[test]
fn golden_android_robot() {
    golden("android_robot.hf", "android_robot");
}

#[test]
fn golden_sake_pot() {
    golden("sake_pot.hf", "sake_pot");
}

/// A plate `|z| <= h` whose thickness is 0.5, 1 and 2 pixel footprints:
/// every pixel whose ray meets the plate inside the box is a hit.
#[test]
fn thin_slab_is_visible() {
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    let (w, hgt) = (48u32, 48u32);
    for fov in [None, Some(30.0)] {
        for pitch in [2.0, 20.0, 70.0] {
            for px in [0.5, 1.0, 2.0] {
                let cam = Camera::orbit(&b, 25.0, pitch, fov);
                let dist = (cam.eye[0].powi(2) + cam.eye[1].powi(2) + cam.eye[2].powi(2)).sqrt();
                let fp = cam.pixel_footprint(dist, w, hgt);
                let half = 0.5 * px * fp;
                let src = format!("plate(x[3], a[1]) {{ plate = {half:e} - abs(x[3]); }}");
                let model = Model::compile(&src).unwrap();
                let s = RenderSettings {
                    size: (w, hgt),
                    bounds: b,
                    yaw: 25.0,
                    pitch,
                    fov,
                    tile_size: 16,
                    ..Default::default()
                };
                let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
                let plate = Aabb::new([-1.0, -1.0, -half], [1.0, 1.0, half]);
                let mut missed = 0;
                let mut expected = 0;
                for y in 0..hgt {
                    for x in 0..w {
                        if cam.ray(x, y, w, hgt).clip(&plate).is_some() {
                            expected += 1;
                            missed += hits.get(x, y).is_none() as u32;
                        }
                    }
                }
                assert!(expected > 0);
                assert_eq!(missed, 0, "fov {fov:?} pitch {pitch} thickness {px} px");
            }
        }
    }
}

/// One pixel's samples: (depths, values), `None` where its ray misses the
/// box.
type Samples = Option<(Vec<f64>, Vec<f64>)>;

/// Brute force: each pixel's ray sampled across the box every `frac` of a
/// pixel footprint (at its entry).
fn ray_samples(model: &Model, cam: &Camera, b: &Aabb, w: u32, h: u32, frac: f64) -> Vec<Samples> {
    let mut ev = BatchEval::new(&model.tape());
    let inputs = Inputs::default();
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let r = cam.ray(x, y, w, h);
            let Some((t0, t1)) = r.clip(b) else {
                out.push(None);
                continue;
            };
            let step = frac * cam.pixel_footprint(t0, w, h);
            let n = ((t1 - t0) / step).ceil() as usize + 1;
            let ts: Vec<f64> = (0..=n)
                .map(|k| t0 + (t1 - t0) * k as f64 / n as f64)
                .collect();
            let (mut xs, mut ys, mut zs) = (vec![], vec![], vec![]);
            for &t in &ts {
                let p = r.at(t);
                xs.push(p[0]);
                ys.push(p[1]);
                zs.push(p[2]);
            }
            let mut v = vec![0.0; xs.len()];
            ev.eval(&xs, &ys, &zs, &inputs, &mut v);
            out.push(Some((ts, v)));
        }
    }
    out
}

/// Brute-force reference: each ray sampled every 1/4 pixel footprint.
fn reference_mask(model: &Model, cam: &Camera, b: &Aabb, w: u32, h: u32) -> Vec<bool> {
    ray_samples(model, cam, b, w, h, 0.25)
        .into_iter()
        .map(|s| s.is_some_and(|(_, v)| v.iter().any(|&f| f >= 0.0)))
        .collect()
}

/// M3 seen almost edge-on to its clipping sphere and along the gyroid's
/// sheets: no more than 1/4 % of pixels (10 of 4096) differ from the dense
/// reference (measured: 0, 4 and 2; each side finds slivers thinner than a
/// sample step that the other misses).
#[test]
fn gyroid_grazing_matches_dense_reference() {
    let src = example("m3_gyroid.hf");
    let model = Model::compile(&src).unwrap();
    let b = bounds_of(&src);
    let (w, h) = (64, 64);
    for (yaw, pitch, fov) in [(0.0, 0.0, None), (45.0, 1.0, Some(40.0)), (0.0, 89.0, None)] {
        let s = RenderSettings {
            yaw,
            pitch,
            fov,
            ..settings(b, w, h)
        };
        let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
        let reference = reference_mask(&model, &s.camera(), &b, w, h);
        let got = mask(&hits);
        let diff = got.iter().zip(&reference).filter(|(a, b)| a != b).count();
        let missed = got
            .iter()
            .zip(&reference)
            .filter(|(a, b)| !**a && **b)
            .count();
        eprintln!("yaw {yaw} pitch {pitch}: {diff} pixels differ ({missed} missed)");
        assert!(
            diff * 400 <= (w * h) as usize,
            "yaw {yaw} pitch {pitch}: {diff} pixels differ ({missed} missed)"
        );
    }
}

/// The golden models' masks against the dense reference: no pixel missed.
#[test]
fn examples_match_dense_reference() {
    for file in ["android_robot.hf", "sake_pot.hf", "m4_rblend10.hf"] {
        let src = example(file);
        let model = Model::compile(&src).unwrap();
        let s = settings(bounds_of(&src), 80, 80);
        let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
        let reference = reference_mask(&model, &s.camera(), &s.bounds, 80, 80);
        let got = mask(&hits);
        let missed = got
            .iter()
            .zip(&reference)
            .filter(|(a, b)| !**a && **b)
            .count();
        let extra = got
            .iter()
            .zip(&reference)
            .filter(|(a, b)| **a && !**b)
            .count();
        assert!(
            missed + extra <= 2,
            "{file}: {missed} missed, {extra} extra"
        );
    }
}

/// Scaling the field by 100 or by 0.01 changes nothing visible.
#[test]
fn scaled_fields_give_identical_masks() {
    for file in ["m3_gyroid.hf", "m4_rblend10.hf", "android_robot.hf"] {
        let src = example(file);
        let b = bounds_of(&src);
        let base_model = Model::compile(&src).unwrap();
        let base = render_hits(&base_model, &settings(b, 48, 40), &CancelToken::new()).unwrap();
        // Wrap the body: my_model = k * (old value).
        let (decl, call) = if base_model.has_attributes {
            (format!(", s[{}]", base_model.s_dim), ", s")
        } else {
            (String::new(), "")
        };
        let a = base_model.a_dim.max(1);
        for k in ["100", "0.01"] {
            let scaled = src.replace("my_model", "inner_model")
                + &format!(
                    "\nmy_model(x[3], a[{a}]{decl})\n{{\n  my_model = {k} * inner_model(x, a{call});\n}}\n"
                );
            let model = Model::compile(&scaled).unwrap_or_else(|d| panic!("{file}: {d:?}"));
            let hits = render_hits(&model, &settings(b, 48, 40), &CancelToken::new()).unwrap();
            assert_eq!(mask(&hits), mask(&base), "{file} scaled by {k}");
        }
    }
}

/// `(r² − |p|²)³` has a zero gradient on its surface: still a full disc, with
/// finite, outward normals.
#[test]
fn zero_gradient_surface() {
    let src = "cubed(x[3], a[1]) { cubed = (0.64 - (x[1]^2 + x[2]^2 + x[3]^2))^3; }";
    let model = Model::compile(src).unwrap();
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    let s = settings(b, 48, 48);
    let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
    let reference = frep_render::synthetic::sphere_hits(&s.camera(), 48, 48, [0.0; 3], 0.8, None);
    let diff = mask(&hits)
        .iter()
        .zip(&mask(&reference))
        .filter(|(a, b)| a != b)
        .count();
    assert!(diff <= 4, "{diff} pixels differ from the analytic disc");
    for h in hits.hits.iter().flatten() {
        let n = h.normal;
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((l - 1.0).abs() < 1e-6, "normal {n:?}");
        let p = h.position;
        let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let c = (n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) / r;
        assert!(c > 0.9, "normal {n:?} at {p:?}");
        assert!((r - 0.8).abs() < 0.01, "hit at radius {r}");
    }
}

#[test]
fn cancel_stops_the_render() {
    let src = example("m3_gyroid.hf");
    let model = Model::compile(&src).unwrap();
    let (cancel, pool) = (CancelToken::new(), ImagePool::default());
    cancel.clone().cancel();
    let s = settings(bounds_of(&src), 64, 64);
    assert_eq!(
        render(&model, &s, &cancel, &pool),
        Err(RenderError::Cancelled)
    );
    assert_eq!(
        render_hits(&model, &s, &cancel).err(),
        Some(RenderError::Cancelled)
    );
    assert!(render(&model, &s, &CancelToken::new(), &pool).is_ok());
}

#[test]
fn size_limits() {
    let model = Model::compile(&example("m1_sphere.hf")).unwrap();
    let mut s = settings(Aabb::new([-1.0; 3], [1.0; 3]), 0, 10);
    assert!(matches!(
        render(&model, &s, &CancelToken::new(), &ImagePool::default()),
        Err(RenderError::BadSize { .. })
    ));
    s.size = (20_000, 10);
    assert!(render(&model, &s, &CancelToken::new(), &ImagePool::default()).is_err());
    // A configured limit holds and is named in the error.
    s.size = (64, 64);
    s.limits = RenderLimits {
        max_side: 64,
        max_pixels: 4000,
    };
    let e = render(&model, &s, &CancelToken::new(), &ImagePool::default()).unwrap_err();
    assert!(matches!(e, RenderError::BadSize { limits, .. } if limits == s.limits));
    assert!(e.to_string().contains("4000 pixels"), "{e}");
    s.limits.max_pixels = 4096;
    assert!(render_hits(&model, &s, &CancelToken::new()).is_ok());
}

/// The Android robot is green (#A4C639) with white eyes.
#[test]
fn attribute_colours() {
    let src = example("android_robot.hf");
    let model = Model::compile(&src).unwrap();
    let mut s = settings(bounds_of(&src), 64, 64);
    s.yaw = 0.0;
    s.pitch = 10.0;
    let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
    let all: Vec<_> = hits.hits.iter().flatten().collect();
    assert!(all.len() > 300);
    let green = all
        .iter()
        .filter(|h| {
            h.color
                .is_some_and(|c| (c[0] - 0.64).abs() < 1e-6 && (c[1] - 0.78).abs() < 1e-6)
        })
        .count();
    assert!(green * 10 > all.len() * 8, "{green} of {}", all.len());
    // Every hit's colour is the attributes' value there (constant over most
    // tiles' hits, taken once per tile by interval; the eyes' tiles point
    // by point), and the eyes are white.
    let mut pe = PointEval::new(model.point_tape());
    let mut white = 0;
    for h in &all {
        let [x, y, z] = h.position;
        pe.eval(x, y, z, &Default::default()).unwrap();
        let want = [1, 2, 3].map(|k| pe.output(k).unwrap().clamp(0.0, 1.0) as f32);
        assert_eq!(h.color, Some(want), "at {:?}", h.position);
        white += (want == [1.0; 3]) as usize;
    }
    assert!(white > 3, "{white} white hits");
    let img = render(&model, &s, &CancelToken::new(), &ImagePool::default()).unwrap();
    let (mut g, mut n) = (0, 0);
    for (i, h) in hits.hits.iter().enumerate() {
        if h.is_some() {
            let p = &img.rgba[i * 4..i * 4 + 3];
            n += 1;
            g += (p[1] > p[0] && p[1] > p[2]) as u32;
        }
    }
    assert!(g * 10 > n * 7, "{g} green pixels of {n}");
}

/// Shaded images from `render` equal shading the hit buffer.
#[test]
fn render_equals_shaded_hits() {
    let src = example("sake_pot.hf");
    let model = Model::compile(&src).unwrap();
    let mut s = settings(bounds_of(&src), 40, 30);
    s.ao = true;
    let img = render(&model, &s, &CancelToken::new(), &ImagePool::default()).unwrap();
    let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
    assert!(hits.ao.is_some());
    assert_eq!(img, frep_render::shade(&hits, &s.lighting));
}

/// Pruning regression: M4 (nine nested R-unions) at 128² needs few interval
/// and point evaluations thanks to the R-function interval rules and
/// per-box tape shortening.
#[test]
fn pruning_regression_m4() {
    let src = example("m4_rblend10.hf");
    let model = Model::compile(&src).unwrap();
    let s = settings(bounds_of(&src), 128, 128);
    let caster = ModelCaster::new(&model, Inputs::default(), s.bounds);
    let cam = s.camera();
    let hits = frep_render::cast_tiled(&caster, &cam, 128, 128, 16);
    let st = caster.stats();
    eprintln!("M4 128²: {st:?}, {} hits", hits.hit_count());
    assert!(hits.hit_count() > 1000);
    assert!(st.interval_evals < INTERVAL_BOUND, "{st:?}");
    assert!(st.point_evals < POINT_BOUND, "{st:?}");
}

/// Measured 9.1 k interval and 131 k point evaluations (1658 hits).
const INTERVAL_BOUND: u64 = 14_000;
/// See [`INTERVAL_BOUND`].
const POINT_BOUND: u64 = 200_000;

/// Normals of a sphere of radius 0.8, small in the image (a few dozen pixels
/// across, so a difference step of a fraction of a pixel would not be
/// negligible against the curvature) and large: within 0.001° of the radial
/// direction, 0.0005° on average. Automatic differentiation gives the
/// gradient at the hit, about 1e-6° off; central differences at ±½ pixel
/// gave 0.02° at 40², a tetrahedron of four points 0.75° at ¼ pixel.
#[test]
fn sphere_normals_are_radial() {
    let model = Model::compile(&example("m1_sphere.hf")).unwrap();
    for (size, worst_deg, mean_deg) in [(40u32, 1e-3f64, 5e-4f64), (200, 1e-3, 5e-4)] {
        let s = settings(Aabb::new([-1.0; 3], [1.0; 3]), size, size);
        let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
        let (mut worst, mut sum, mut count) = (0.0f64, 0.0, 0);
        for h in hits.hits.iter().flatten() {
            let (n, p) = (h.normal, h.position);
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let c = (n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) / r;
            let deg = c.clamp(-1.0, 1.0).acos().to_degrees();
            worst = worst.max(deg);
            sum += deg;
            count += 1;
        }
        assert!(count > size as usize * size as usize / 8, "{count} hits");
        let mean = sum / count as f64;
        assert!(worst < worst_deg, "{size}²: worst {worst}°");
        assert!(mean < mean_deg, "{size}²: mean {mean}°");
    }
}

/// Every hit lies on the surface: its distance to the surface, to first
/// order `|f| / |∇f|` at the hit, is within 1/48 of a pixel footprint for
/// 99 % of the hits and all of a sphere's, and 1/200 on average. (Hits are
/// taken at a bracket's false-position point where one Newton step would
/// move them at most 1/64 of a footprint, else refined to 1/16 and then one
/// secant step. Where the surface has a crease the first-order estimate is
/// not a distance: the gyroid clipped by a sphere has a few hits at 0.1.)
/// Hits on the model box's faces (solids cut open by it) are left out.
#[test]
fn hits_lie_on_the_surface() {
    use frep_core::eval::grad::GradEval;
    for file in [
        "m1_sphere.hf",
        "m3_gyroid.hf",
        "m4_rblend10.hf",
        "android_robot.hf",
    ] {
        let src = example(file);
        let model = Model::compile(&src).unwrap();
        let b = bounds_of(&src);
        let mut ge = GradEval::new(&model.tape());
        for fov in [Some(30.0), None] {
            let (w, h) = (96, 96);
            let s = RenderSettings {
                fov,
                ..settings(b, w, h)
            };
            let cam = s.camera();
            let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
            let mut dist = Vec::new();
            for hit in hits.hits.iter().flatten() {
                let p = hit.position;
                let on_face = (0..3).any(|k| {
                    let tol = 1e-9 * (b.max[k] - b.min[k]);
                    (p[k] - b.min[k]).abs() < tol || (p[k] - b.max[k]).abs() < tol
                });
                let g = ge.eval(p[0], p[1], p[2], &Inputs::default());
                let len = (g.dx * g.dx + g.dy * g.dy + g.dz * g.dz).sqrt();
                if on_face || len == 0.0 || !len.is_finite() {
                    continue;
                }
                dist.push(g.v.abs() / len / cam.pixel_footprint(hit.t, w, h));
            }
            assert!(dist.len() > 500, "{file} {fov:?}: {} hits", dist.len());
            dist.sort_by(f64::total_cmp);
            let mean = dist.iter().sum::<f64>() / dist.len() as f64;
            let p99 = dist[dist.len() * 99 / 100];
            let worst = dist[dist.len() - 1];
            eprintln!("{file} {fov:?}: mean {mean}, 99 % {p99}, worst {worst} footprints");
            assert!(
                mean <= 1.0 / 200.0,
                "{file} {fov:?}: mean {mean} footprints"
            );
            assert!(
                p99 <= 1.0 / 48.0,
                "{file} {fov:?}: 99 % within {p99} footprints"
            );
            if file == "m1_sphere.hf" {
                assert!(
                    worst <= 1.0 / 48.0,
                    "{file} {fov:?}: worst {worst} footprints"
                );
            }
        }
    }
}

/// Brute-force first crossings: per pixel, `(t_prev, t)` with the sample at
/// `t` the first inside one and `t_prev` the sample before it (each ray
/// sampled every 1/8 pixel footprint from where it enters the box).
fn reference_depths(
    model: &Model,
    cam: &Camera,
    b: &Aabb,
    w: u32,
    h: u32,
) -> Vec<Option<(f64, f64)>> {
    ray_samples(model, cam, b, w, h, 0.125)
        .into_iter()
        .map(|s| {
            let (ts, v) = s?;
            let k = v.iter().position(|&f| f >= 0.0)?;
            Some((ts[k.saturating_sub(1)], ts[k]))
        })
        .collect()
}

/// Solids cut open by the model box, seen obliquely (the box's entry depth
/// varies across every leaf, and sub-slabs at the entry are inside
/// throughout): every hit is at the first crossing the dense reference
/// finds, and no ray entering the solid is missed.
#[test]
fn box_cut_solids_hit_at_their_first_crossing() {
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    for src in [
        "m(x[3], a[1]) { m = 1.3 - sqrt(x[1]^2 + x[2]^2 + x[3]^2); }",
        "m(x[3], a[1]) { m = 0.2 + x[1] + 0.5*x[2] - 0.3*x[3]; }",
        "m(x[3], a[1]) { m = 0.3 - x[2] + 0.2*sin(4*x[1]); }",
    ] {
        let model = Model::compile(src).unwrap();
        for (yaw, pitch, fov) in [
            (30.0, 20.0, Some(30.0)),
            (65.0, 40.0, Some(60.0)),
            (-20.0, -35.0, None),
            (10.0, 80.0, Some(45.0)),
        ] {
            let (w, h) = (96, 96);
            let s = RenderSettings {
                yaw,
                pitch,
                fov,
                tile_size: 32,
                ..settings(b, w, h)
            };
            let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
            let cam = s.camera();
            let reference = reference_depths(&model, &cam, &b, w, h);
            let mut bad = Vec::new();
            for (i, (got, want)) in hits.hits.iter().zip(&reference).enumerate() {
                let (x, y) = (i as u32 % w, i as u32 / w);
                match (got, want) {
                    (Some(g), Some((t_prev, t))) => {
                        let tol = cam.pixel_footprint(*t, w, h);
                        if g.t < t_prev - tol || g.t > t + tol {
                            bad.push(format!("({x},{y}) t {} not in [{t_prev}, {t}]", g.t));
                        }
                    }
                    (None, Some((_, t))) => bad.push(format!("({x},{y}) missed at t {t}")),
                    _ => {}
                }
            }
            assert!(
                bad.is_empty(),
                "{src} yaw {yaw} pitch {pitch} fov {fov:?}: {} bad pixels, e.g. {:?}",
                bad.len(),
                &bad[..bad.len().min(5)]
            );
        }
    }
}

/// Rays down the bore of a tube seen along its axis pass leaf after leaf
/// of frustum boxes that hold the wall, without a crossing: after a few
/// such slabs one interval evaluation over the rest of each ray shows it
/// is outside, and the ray is searched no further. The hits are those of a
/// caster that never does this (the same pixels, depths within the
/// refinement tolerance), for far fewer point evaluations; a perspective
/// view gives the same hits too.
#[test]
fn rays_down_a_tube_bore_are_pruned() {
    let src = example("cylinder.hf");
    let model = Model::compile(&src).unwrap();
    let b = bounds_of(&src);
    let n = 128;
    for fov in [None, Some(30.0)] {
        let cam = Camera::orbit(&b, 0.0, 90.0, fov);
        let cast = |prune_after: u32| {
            let mut caster = ModelCaster::new(&model, Inputs::default(), b);
            caster.prune_after = prune_after;
            // (The pruning of the general caster, not the whole-ray
            // closed form.)
            caster.csg = false;
            let hits = frep_render::cast_tiled(&caster, &cam, n, n, 16);
            (hits, caster.stats())
        };
        let (full, full_st) = cast(0);
        let (pruned, pruned_st) = cast(3);
        eprintln!("tube {fov:?}: {full_st:?} → {pruned_st:?}");
        assert!(full.hit_count() > 300, "{}", full.hit_count());
        assert_eq!(mask(&full), mask(&pruned), "{fov:?}");
        let foot = 2.0 * b.radius() / n as f64;
        for (a, p) in full.hits.iter().zip(&pruned.hits) {
            if let (Some(a), Some(p)) = (a, p) {
                assert!((a.t - p.t).abs() <= foot / 8.0, "{} vs {}", a.t, p.t);
            }
        }
        if fov.is_none() {
            assert!(
                2 * pruned_st.point_evals < full_st.point_evals,
                "{full_st:?} → {pruned_st:?}"
            );
        }
    }
}

/// Orthographic views straight along each axis, both ways: the leaves are
/// evaluated as lines (functions of the other two coordinates once per ray,
/// of the axis one once per depth), and the hits are those of evaluating
/// point by point, bit for bit, with the same work counted. A view just off
/// the axis is evaluated point by point.
#[test]
fn lines_along_an_axis_equal_points() {
    let gyroid = example("m3_gyroid.hf");
    let mixed = "my_model(x[3], a[1]) { my_model = 0.7 - sqrt(x[1]^2 + x[2]^2 + x[3]^2) \
                 + 0.2 * sin(9 * x[1]) * cos(7 * x[3]) + 0.1 * exp(-x[2]); }";
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    for src in [gyroid.as_str(), mixed] {
        let model = Model::compile(src).unwrap();
        for (dir, up) in [
            ([0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
            ([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
            ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            ([0.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
            ([1e-3, 0.0, -1.0], [0.0, 1.0, 0.0]),
        ] {
            let eye = [-3.0 * dir[0], -3.0 * dir[1], -3.0 * dir[2]];
            let cam = Camera::look_at(
                eye,
                [0.0; 3],
                up,
                frep_render::camera::Projection::Orthographic { half_extent: 1.0 },
            );
            // One thread: the work counted depends on the order tiles meet
            // a worker's scratch (its pruning odds); the hits do not.
            let one = pool(1);
            let cast = |lines: bool| {
                let mut c = ModelCaster::new(&model, Inputs::default(), b);
                c.lines = lines;
                let hits = one.install(|| cast_tiled(&c, &cam, 72, 64, 16));
                (hits, c.stats())
            };
            let (on, on_st) = cast(true);
            let (off, off_st) = cast(false);
            assert!(on.hit_count() > 1000, "{dir:?}: {} hits", on.hit_count());
            for (i, (a, b)) in on.hits.iter().zip(&off.hits).enumerate() {
                let bits = |h: &Option<frep_render::Hit>| {
                    h.map(|h| {
                        let mut v = vec![h.t.to_bits()];
                        v.extend(h.position.iter().chain(&h.normal).map(|x| x.to_bits()));
                        v
                    })
                };
                assert_eq!(bits(a), bits(b), "{dir:?}: pixel {i}");
            }
            assert_eq!(on_st.point_evals, off_st.point_evals, "{dir:?}");
            assert_eq!(off_st.line_points, 0);
            if dir[0] == 1e-3 {
                assert_eq!(on_st.line_points, 0, "off the axis");
            } else {
                // Most samples are in leaves of tiles whose rays share one
                // depth range.
                assert!(
                    2 * on_st.line_points > on_st.point_evals,
                    "{dir:?}: {on_st:?}"
                );
            }
        }
    }
}

/// `render` shades tile by tile and fills the tiles where no ray hit with
/// the background without shading them: the same image as shading the
/// whole hit buffer, partial edge tiles and ambient occlusion included.
#[test]
fn tiled_render_equals_shaded_hits() {
    let src = "my_model(x[3], a[1]) { my_model = 0.5 - sqrt((x[1] - 0.2)^2 + x[2]^2 + x[3]^2); }";
    let model = Model::compile(src).unwrap();
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    for (fov, ao) in [(None, false), (Some(40.0), false), (Some(40.0), true)] {
        let s = RenderSettings {
            pitch: 60.0,
            fov,
            ao,
            ..settings(b, 100, 90)
        };
        let img = render(&model, &s, &CancelToken::new(), &ImagePool::default()).unwrap();
        let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
        assert!(hits.hit_count() > 300, "{fov:?}: {} hits", hits.hit_count());
        let whole = shade(&hits, &s.lighting);
        assert_eq!(img.rgba, whole.rgba, "{fov:?}, ao {ao}");
        // The corners are background (tiles without a hit), rows of the
        // gradient, opaque.
        assert_ne!(img.pixel(0, 0), img.pixel(0, 89));
        assert_eq!(img.pixel(0, 0), img.pixel(99, 0));
        assert_eq!(img.pixel(0, 0)[3], 255);
    }
}

/// A small sphere in the middle of a top view: the tiles around it are found
/// empty by one interval evaluation each (their rays never set up), and the
/// pixels are those of the dense reference.
#[test]
fn empty_tiles_are_skipped_whole() {
    let src = "my_model(x[3], a[1]) { my_model = 0.3 - sqrt(x[1]^2 + x[2]^2 + x[3]^2); }";
    let model = Model::compile(src).unwrap();
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    let (w, h) = (128, 128);
    for fov in [None, Some(40.0)] {
        let s = RenderSettings {
            pitch: 90.0,
            fov,
            ..settings(b, w, h)
        };
        let caster = ModelCaster::new(&model, Inputs::default(), b);
        let cam = s.camera();
        let hits = frep_render::cast_tiled(&caster, &cam, w, h, s.tile_size);
        let st = caster.stats();
        // 64 tiles of 16²; the sphere's disk (about 11 pixels in radius:
        // the view frames the box's bounding sphere) meets at most 16.
        assert!(st.empty_tiles >= 48, "{fov:?}: {st:?}");
        let reference = reference_mask(&model, &cam, &b, w, h);
        let got = mask(&hits);
        let diff = got.iter().zip(&reference).filter(|(a, b)| a != b).count();
        assert!(hits.hit_count() > 200, "{fov:?}: {} hits", hits.hit_count());
        assert!(
            diff <= 2,
            "{fov:?}: {diff} pixels differ from the reference"
        );
    }
}

/// The hits and counters of a view cast with the closed form on and off.
type OnOff = [(HitBuffer, CastStats); 2];

/// `model` cast at `w`×`h` in 16² tiles with the closed form on and off
/// ([`ModelCaster::exact`]), with each cast's counters. Set expressions over
/// quadrics are not solved whole ([`ModelCaster::csg`] off): these casts
/// test the slabs.
fn cast_exact_on_off(model: &Model, b: Aabb, cam: &Camera, w: u32, h: u32) -> OnOff {
    [true, false].map(|exact| {
        let mut c = ModelCaster::new(model, Inputs::default(), b);
        c.exact = exact;
        c.csg = false;
        (cast_tiled(&c, cam, w, h, 16), c.stats())
    })
}

/// The image side of [`two_views_on_off`].
const SMALL: u32 = 64;

/// For the plane and quadric tests: `model` over the box
/// `[-1, 1]² × [-1.2, 1.2]` in a top view along an axis and a perspective
/// view, [`SMALL`]² pixels, each view's yaw, camera and the casts of
/// [`cast_exact_on_off`].
fn two_views_on_off(model: &Model) -> Vec<(f64, Camera, OnOff)> {
    let b = Aabb::new([-1.0, -1.0, -1.2], [1.0, 1.0, 1.2]);
    [(0.0, 90.0, None), (30.0, 50.0, Some(30.0))]
        .into_iter()
        .map(|(yaw, pitch, fov)| {
            let cam = RenderSettings {
                yaw,
                pitch,
                fov,
                ..settings(b, SMALL, SMALL)
            }
            .camera();
            let casts = cast_exact_on_off(model, b, &cam, SMALL, SMALL);
            (yaw, cam, casts)
        })
        .collect()
}

/// The rays of quadric slabs solved in blocks
/// ([`ModelCaster::quadric_blocks`]) get the hits they get one at a time,
/// bit for bit: depths, positions and normals, on the quadric examples and
/// an ellipsoid, in an orthographic view along an axis, an oblique one and
/// two perspective views. On one thread: a shortened tape's quadric is
/// fitted where the first tile that needs it on a thread meets it, so the
/// last bits of its coefficients, and of the hits, depend on which tiles
/// each thread took.
#[test]
fn quadric_blocks_equal_single_rays() {
    let mut models: Vec<(String, String)> = [
        "m1_sphere.hf",
        "sphere.hf",
        "semi_sphere.hf",
        "m2_spheres100.hf",
        "closed_cylinder.hf",
        "cylinder.hf",
    ]
    .iter()
    .map(|f| (f.to_string(), example(f)))
    .collect();
    models.push((
        "ellipsoid".into(),
        "my_model(x[3], a[1]) { my_model = 0.6 - (x[1] - 0.1)^2 - 2 * x[2]^2 \
         - 0.5 * x[3]^2 - 0.4 * x[1] * x[3]; }"
            .into(),
    ));
    let views = [
        (0.0, 90.0, None),
        (35.0, 25.0, None),
        (30.0, 20.0, Some(30.0)),
        (200.0, -10.0, Some(60.0)),
    ];
    let bits = |h: &Option<frep_render::Hit>| {
        h.map(|h| {
            let v = [h.t, h.position[0], h.position[1], h.position[2]];
            let n = h.normal;
            [v[0], v[1], v[2], v[3], n[0], n[1], n[2]].map(f64::to_bits)
        })
    };
    let one_thread = pool(1);
    for (name, src) in &models {
        let model = Model::compile(src).unwrap();
        let b = if src.contains("-- bounds:") {
            bounds_of(src)
        } else {
            Aabb::new([-1.0; 3], [1.0; 3])
        };
        for &(yaw, pitch, fov) in &views {
            let cam = Camera::orbit(&b, yaw, pitch, fov);
            let cast = |blocks: bool| {
                let mut c = ModelCaster::new(&model, Inputs::default(), b);
                c.quadric_blocks = blocks;
                c.csg = false;
                let hits = one_thread.install(|| cast_tiled(&c, &cam, 96, 96, 32));
                (hits, c.stats())
            };
            let ((on, on_st), (off, off_st)) = (cast(true), cast(false));
            assert!(
                on.hit_count() > 200,
                "{name} yaw {yaw}: {} hits",
                on.hit_count()
            );
            assert!(on_st.exact_rays > 0, "{name} yaw {yaw}: {on_st:?}");
            assert_eq!(on_st, off_st, "{name} yaw {yaw}: the work differs");
            for (j, (a, o)) in on.hits.iter().zip(&off.hits).enumerate() {
                assert_eq!(
                    bits(a),
                    bits(o),
                    "{name} yaw {yaw} pitch {pitch}: pixel {j}"
                );
            }
        }
    }
}

/// The pixels hit in `on` or `off` but not both (`cam`'s casts), asserting
/// that the depths of the others agree within a quarter of a pixel
/// footprint.
fn exact_agrees(what: &str, cam: &Camera, on: &HitBuffer, off: &HitBuffer) -> usize {
    let (w, h) = (on.width, on.height);
    let mut differ = 0;
    for (i, (a, o)) in on.hits.iter().zip(&off.hits).enumerate() {
        match (a, o) {
            (Some(a), Some(o)) => {
                let fp = cam.pixel_footprint(o.t, w, h);
                assert!(
                    (a.t - o.t).abs() <= 0.25 * fp,
                    "{what}: pixel {i} at {} and {} (footprint {fp})",
                    a.t,
                    o.t
                );
            }
            (None, None) => {}
            _ => differ += 1,
        }
    }
    differ
}

/// Slabs settled in closed form where the shortened tape is a polynomial of
/// degree 2 ([`ModelCaster::exact`]) give the hits of sampling them: on
/// every example, in a top view along an axis and two perspective views,
/// the same pixels are hit (but for a few grazing ones), at depths within a
/// quarter of a pixel footprint (measured: no pixel differs at 96²). The
/// closed form is used on the quadric models, M1's `0.8 − sqrt(…)`
/// included.
#[test]
fn exact_slabs_match_sampling() {
    let dir = format!("{}/../../examples", env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "hf"))
        .collect();
    files.sort();
    assert!(files.len() >= 11, "{} examples", files.len());
    let (w, h) = (96, 96);
    let views = [
        (0.0, 90.0, None),
        (30.0, 20.0, Some(30.0)),
        (200.0, -10.0, Some(30.0)),
    ];
    for path in &files {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let src = std::fs::read_to_string(path).unwrap();
        let model = Model::compile(&src).unwrap();
        let b = bounds_of(&src);
        let mut exact_rays = 0;
        for (yaw, pitch, fov) in views {
            let cam = RenderSettings {
                yaw,
                pitch,
                fov,
                ..settings(b, w, h)
            }
            .camera();
            let [(on, on_st), (off, off_st)] = cast_exact_on_off(&model, b, &cam, w, h);
            assert_eq!(off_st.exact_rays, 0);
            exact_rays += on_st.exact_rays;
            let differ = exact_agrees(&format!("{name} yaw {yaw}"), &cam, &on, &off);
            assert!(
                off.hit_count() > 200,
                "{name} yaw {yaw}: {} hits",
                off.hit_count()
            );
            assert!(differ <= 3, "{name} yaw {yaw}: {differ} pixels differ");
        }
        match name.as_str() {
            // M1 is `0.8 − sqrt(x² + y² + z²)`, a root gap.
            "sphere" | "semi_sphere" | "closed_cylinder" | "cylinder" | "m4_rblend10"
            | "m1_sphere" => {
                assert!(
                    exact_rays > 1000,
                    "{name}: {exact_rays} rays settled in closed form"
                )
            }
            _ => {}
        }
    }
}

/// Planes take no samples: where the tape shortened for a box is affine in
/// the point (a slab's faces, a cap, a sloped plane in a perspective view),
/// each ray's crossing is computed from the plane's coefficients and the
/// hit recorded with the plane's normal, no gradient evaluated per hit.
/// The hits are those of sampling, at the same depths and with the same
/// normals; a model with attribute colours gets its colours on every hit
/// (also where a box is inside throughout, which once had none).
#[test]
fn planes_take_no_samples() {
    let slab = "my_model(x[3], a[1]) { my_model = (0.5 - x[3]) & (x[3] + 1); }";
    let sloped = "my_model(x[3], a[1]) { my_model = (0.3 - 0.4 * x[1] - x[3]) & (x[3] + 1); }";
    let coloured = "my_model(x[3], a[1], s[3]) { s[1] = 0.2; s[2] = 0.5; s[3] = x[1]; \
                    my_model = (0.5 - x[3]) & (x[3] + 1); }";
    for (name, src) in [("slab", slab), ("sloped", sloped), ("coloured", coloured)] {
        let model = Model::compile(src).unwrap();
        for (yaw, _, [(on, on_st), (off, off_st)]) in two_views_on_off(&model) {
            let hits = off.hit_count();
            assert!(hits > 1000, "{name} yaw {yaw}: {hits} hits");
            assert_eq!(on.hit_count(), hits, "{name} yaw {yaw}");
            for (a, o) in on.hits.iter().zip(&off.hits) {
                let (Some(a), Some(o)) = (a, o) else {
                    assert_eq!(a.is_some(), o.is_some());
                    continue;
                };
                assert!((a.t - o.t).abs() <= 1e-9, "{name}: at {} and {}", a.t, o.t);
                for k in 0..3 {
                    assert!((a.normal[k] - o.normal[k]).abs() <= 1e-9, "{name}: normals");
                }
                let (ca, co) = (a.color.unwrap_or([9.0; 3]), o.color.unwrap_or([9.0; 3]));
                let near = (0..3).all(|k| (ca[k] - co[k]).abs() <= 1e-6);
                assert!(near, "{name}: colours {ca:?} and {co:?}");
            }
            if name == "coloured" {
                // Every hit, those at the model box's faces (inside boxes)
                // included.
                assert!(on.hits.iter().flatten().all(|h| h.color.is_some()));
                assert!(off.hits.iter().flatten().all(|h| h.color.is_some()));
            } else {
                // Sampling evaluates a gradient per hit found by a
                // crossing; the plane's hits need none, nor samples.
                assert!(off_st.point_evals > 2 * hits as u64, "{off_st:?}");
                assert_eq!(on_st.point_evals, 0, "{name} yaw {yaw}: {on_st:?}");
                assert!(
                    on_st.grad_evals * 8 < hits as u64,
                    "{name} yaw {yaw}: {on_st:?}, {hits} hits"
                );
            }
        }
    }
}

/// Quadrics take no samples: where the tape shortened for a box is a
/// polynomial of degree 2 in the point (a sphere, a sloped ellipsoid, a
/// cylinder) or a root gap `k − sqrt(p)` (M1's form), each ray's polynomial
/// comes from the quadric's coefficients and a crossing that checks out is
/// the hit with the quadric's normal: no point evaluations and no gradient
/// per hit. The hits are sampling's (the same pixels, depths within 1/16 of
/// a footprint) and their normals the field's gradient's there (within
/// 1e-9); a model with attribute colours gets its colours on every hit.
#[test]
fn quadrics_take_no_samples() {
    let models = [
        (
            "sphere",
            "my_model(x[3], a[1]) { my_model = 0.8 - x[1]^2 - x[2]^2 - x[3]^2; }",
        ),
        (
            "ellipsoid",
            "my_model(x[3], a[1]) { my_model = 0.6 - (x[1] - 0.1)^2 - 2 * x[2]^2 \
             - 0.5 * x[3]^2 - 0.4 * x[1] * x[3]; }",
        ),
        (
            "cylinder",
            "my_model(x[3], a[1]) { my_model = 0.5 - x[1]^2 - x[2]^2; }",
        ),
        (
            "root gap",
            "my_model(x[3], a[1]) { my_model = 0.8 - sqrt(x[1]^2 + x[2]^2 + x[3]^2); }",
        ),
        (
            "coloured",
            "my_model(x[3], a[1], s[3]) { s[1] = 0.2; s[2] = 0.5; s[3] = x[1]; \
             my_model = 0.8 - x[1]^2 - x[2]^2 - x[3]^2; }",
        ),
    ];
    for (name, src) in models {
        let model = Model::compile(src).unwrap();
        let mut grad = GradEval::new(&model.tape());
        for (yaw, cam, [(on, on_st), (off, off_st)]) in two_views_on_off(&model) {
            let hits = off.hit_count();
            assert!(hits > 300, "{name} yaw {yaw}: {hits} hits");
            let mut differ = 0;
            for (a, o) in on.hits.iter().zip(&off.hits) {
                let (Some(a), Some(o)) = (a, o) else {
                    differ += usize::from(a.is_some() != o.is_some());
                    continue;
                };
                let fp = cam.pixel_footprint(o.t, SMALL, SMALL);
                assert!(
                    (a.t - o.t).abs() <= fp / 16.0,
                    "{name}: at {} and {}",
                    a.t,
                    o.t
                );
                let (ca, co) = (a.color.unwrap_or([9.0; 3]), o.color.unwrap_or([9.0; 3]));
                let near = (0..3).all(|k| (ca[k] - co[k]).abs() <= 1e-3);
                assert!(near, "{name}: colours {ca:?} and {co:?}");
                // The normal is sampling's (a model box face's where the
                // box cuts the solid open) or the field's gradient's at
                // the hit.
                if a.normal == o.normal {
                    continue;
                }
                let [x, y, z] = a.position;
                let g = grad.eval(x, y, z, &Inputs::default()).gradient();
                let len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
                for k in 0..3 {
                    let d = (a.normal[k] + g[k] / len).abs();
                    assert!(d <= 1e-9, "{name}: normal {:?}, gradient {g:?}", a.normal);
                }
            }
            assert!(differ <= 2, "{name} yaw {yaw}: {differ} pixels differ");
            assert!(on_st.exact_rays >= hits as u64, "{name}: {on_st:?}");
            if name == "coloured" {
                assert!(on.hits.iter().flatten().all(|h| h.color.is_some()));
            } else {
                // Sampling evaluates points along every ray and a gradient
                // per hit; the quadric's rays need neither.
                assert!(off_st.point_evals > 2 * hits as u64, "{off_st:?}");
                assert!(
                    on_st.point_evals * 20 < hits as u64 && on_st.grad_evals * 20 < hits as u64,
                    "{name} yaw {yaw}: {on_st:?}, {hits} hits"
                );
            }
        }
    }
}

/// The caster's samples, refinement and normals with the fast `sin`/`cos`
/// ([`Trig::Fast`], the default) find the hits of the exact ones
/// ([`Trig::Exact`]) on the gyroid (M3) and a field of lone `sin` and
/// `cos`, in a perspective turntable view and a top view: the same pixels
/// hit, at depths within a millionth of a pixel footprint, normals within
/// `1e-9`.
#[test]
fn fast_trig_finds_the_exact_hits() {
    let gyroid = example("m3_gyroid.hf");
    let lone = "my_model(x[3], a[1]) { my_model = 0.6 - sqrt(x[1]^2 + x[2]^2 + x[3]^2) \
                + 0.15 * sin(11 * x[1] + 2 * x[3]) - 0.1 * cos(9 * x[2] * x[3]); }";
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    for src in [gyroid.as_str(), lone] {
        let model = Model::compile(src).unwrap();
        for (yaw, pitch, fov) in [(30.0, 25.0, Some(35.0)), (0.0, 90.0, None)] {
            let s = RenderSettings {
                yaw,
                pitch,
                fov,
                ..settings(b, 120, 100)
            };
            let cam = s.camera();
            let cast = |trig: Trig| {
                let mut c = ModelCaster::new(&model, Inputs::default(), b);
                c.trig = trig;
                cast_tiled(&c, &cam, 120, 100, 16)
            };
            assert_eq!(
                ModelCaster::new(&model, Inputs::default(), b).trig,
                Trig::Fast
            );
            let (fast, exact) = (cast(Trig::Fast), cast(Trig::Exact));
            assert!(exact.hit_count() > 800, "{yaw}: {} hits", exact.hit_count());
            assert_eq!(mask(&fast), mask(&exact), "{yaw}: pixels hit");
            let rays = cam.rays(120, 100);
            for (i, (f, e)) in fast.hits.iter().zip(&exact.hits).enumerate() {
                let (Some(f), Some(e)) = (f, e) else { continue };
                let foot = rays.pixel_footprint(e.t);
                assert!(
                    (f.t - e.t).abs() <= 1e-6 * foot,
                    "{yaw}: pixel {i}: {} vs {}",
                    f.t,
                    e.t
                );
                let unit = |n: [f64; 3]| {
                    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                    n.map(|v| v / l)
                };
                let (nf, ne) = (unit(f.normal), unit(e.normal));
                for k in 0..3 {
                    assert!(
                        (nf[k] - ne[k]).abs() <= 1e-9,
                        "{yaw}: pixel {i}: normals {nf:?} vs {ne:?}"
                    );
                }
            }
        }
    }
}

/// Models that are set expressions over quadrics ([`ModelCaster::csg`]):
/// the examples of that form and others (unions, differences, `min` and
/// `max`, a negation, a sloped ellipsoid cut by a plane, a parameter in a
/// leaf, root gaps `k − sqrt(p)` (M1's form), a slab whose face lies on
/// the model box's, where the rays enter on a leaf's surface and are left
/// to the general caster).
fn set_expression_models() -> Vec<(String, String, Aabb)> {
    let unit = Aabb::new([-1.0; 3], [1.0; 3]);
    let mut models: Vec<(String, String, Aabb)> = [
        "semi_sphere.hf",
        "sphere.hf",
        "closed_cylinder.hf",
        "cylinder.hf",
        "m1_sphere.hf",
    ]
    .iter()
    .map(|f| {
        let src = example(f);
        let b = bounds_of(&src);
        (f.to_string(), src, b)
    })
    .collect();
    for (name, body) in [
        (
            "union",
            "my_model = (0.3 - (x[1] - 0.3)^2 - x[2]^2 - x[3]^2) | (0.2 - (x[1] + 0.4)^2 - x[2]^2 - x[3]^2);",
        ),
        (
            "difference",
            "my_model = (0.7 - x[1]^2 - x[2]^2 - x[3]^2) \\ (0.1 - x[1]^2 - x[3]^2);",
        ),
        (
            "min_max",
            "my_model = max(min(0.5 - x[1]^2 - x[2]^2 - x[3]^2, x[3] + 0.2), 0.05 - (x[1] - 0.6)^2 - x[2]^2 - x[3]^2);",
        ),
        (
            "negation",
            "my_model = -(x[1]^2 + x[2]^2 + x[3]^2 - 0.6) & -(0.1 - (x[1] - 0.4)^2 - x[2]^2 - (x[3] - 0.3)^2);",
        ),
        (
            "sloped",
            "my_model = (0.6 - (x[1] - 0.1)^2 - 2 * x[2]^2 - 0.5 * x[3]^2 - 0.4 * x[1] * x[3]) & (0.2 - 0.5 * x[1] - x[3]);",
        ),
        (
            "root gaps",
            "my_model = (0.7 - sqrt((x[1] - 0.1)^2 + x[2]^2 + x[3]^2)) \\ (0.25 - sqrt(x[1]^2 + x[3]^2));",
        ),
        (
            "parameter",
            "my_model = (a[1] - x[1]^2 - x[2]^2 - x[3]^2) & (x[1] + x[2] + 0.3);",
        ),
    ] {
        let src = format!("my_model(x[3], a[1]) {{ {body} }}");
        models.push((name.into(), src, unit));
    }
    models.push((
        "slab on the box".into(),
        "my_model(x[3], a[1]) { my_model = (0.5 - x[3]) & (x[3] + 1) & (0.8 - x[1]^2 - x[2]^2); }"
            .into(),
        Aabb::new([-1.0, -1.0, -1.0], [1.0, 1.0, 0.5]),
    ));
    models
}

/// The views of the set-expression tests: orthographic along an axis and
/// oblique, and two perspective views (one from below).
const CSG_VIEWS: [(f64, f64, Option<f64>); 4] = [
    (0.0, 90.0, None),
    (35.0, 25.0, None),
    (30.0, 20.0, Some(30.0)),
    (200.0, -30.0, Some(60.0)),
];

/// Casts `model` in view `cam` at 96² with the closed form on set
/// expressions ([`ModelCaster::csg`]) on and off, and checks it against the
/// general caster: the same pixels but for at most 3 that only the general
/// caster hits, and slivers (at most 1 in 50 hits) that only the closed
/// form hits, or hits before the general caster's, where the ray is inside
/// just past the hit; other depths within 1/16 of a pixel footprint; where
/// `normals`, each normal the general caster's (a box face's where the box
/// cuts the solid open) or the field's gradient's at the hit (near an
/// edge the general caster's hit, a fraction of a footprint off, has the
/// R-function's gradient there, which blends two leaves'). Returns the
/// counters on and off and the general caster's hit count.
fn against_general(
    what: &str,
    model: &Model,
    inputs: &Inputs,
    b: Aabb,
    cam: &Camera,
    normals: bool,
) -> (CastStats, CastStats, usize) {
    let (w, h) = (96, 96);
    let mut grad = GradEval::new(&model.tape());
    let mut point = PointEval::new(model.tape());
    let cast = |csg: bool| {
        let mut c = ModelCaster::new(model, inputs.clone(), b);
        c.csg = csg;
        (cast_tiled(&c, cam, w, h, 16), c.stats())
    };
    let ((on, on_st), (off, off_st)) = (cast(true), cast(false));
    let hits = off.hit_count();
    let (mut differ, mut slivers) = (0, 0);
    for (i, (a, o)) in on.hits.iter().zip(&off.hits).enumerate() {
        let mut sliver = |a: &frep_render::Hit| {
            let ray = cam.ray(i as u32 % w, i as u32 / w, w, h);
            let p = ray.at(a.t + 1e-7 * (1.0 + a.t));
            let f = point.eval(p[0], p[1], p[2], inputs).unwrap();
            assert!(f >= 0.0, "{what}: pixel {i}: {f} past {a:?}");
            slivers += 1;
        };
        let (Some(a), Some(o)) = (a, o) else {
            if let Some(a) = a {
                sliver(a);
            }
            differ += usize::from(o.is_some());
            continue;
        };
        let fp = cam.pixel_footprint(o.t, w, h);
        if a.t < o.t - fp / 16.0 {
            sliver(a);
            continue;
        }
        assert!(
            (a.t - o.t).abs() <= fp / 16.0,
            "{what}: pixel {i} at {} and {} (footprint {fp})",
            a.t,
            o.t
        );
        if a.normal == o.normal || !normals {
            continue;
        }
        let [x, y, z] = a.position;
        let g = grad.eval(x, y, z, inputs).gradient();
        let len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        // (Normals need not be unit vectors: compared as directions.)
        let n = a.normal;
        let nl = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        for k in 0..3 {
            assert!(
                (n[k] / nl + g[k] / len).abs() <= 1e-7,
                "{what}: pixel {i} normals {:?} and {:?}, gradient {g:?}",
                a.normal,
                o.normal
            );
        }
    }
    assert!(differ <= 3, "{what}: {differ} pixels missed");
    assert!(slivers <= hits / 50, "{what}: {slivers} slivers");
    (on_st, off_st, hits)
}

/// Set expressions over quadrics solved in closed form
/// ([`ModelCaster::csg`]) give the general caster's hits: the same pixels
/// but for a few on edges and silhouettes, depths within 1/16 of a pixel
/// footprint, the same normals (within 1e-6), with no samples taken; the
/// slab whose face lies on the model box's is cast the general way where
/// its rays enter on that face. Models of other forms are not taken.
#[test]
fn set_expressions_match_the_general_caster() {
    let parameter = Inputs::with_params(&[0.5]);
    for (name, src, b) in set_expression_models() {
        let model = Model::compile(&src).unwrap();
        let inputs = if name == "parameter" {
            parameter.clone()
        } else {
            Inputs::default()
        };
        for (yaw, pitch, fov) in CSG_VIEWS {
            let cam = Camera::orbit(&b, yaw, pitch, fov);
            let what = format!("{name} yaw {yaw}");
            // (The slab on the box has rays of the general caster, whose
            // normals near its edges are the R-function's.)
            let normals = name != "slab on the box";
            let (on_st, off_st, hits) = against_general(&what, &model, &inputs, b, &cam, normals);
            assert!(hits > 150, "{what}: {hits} hits");
            // Solved in closed form: no samples (the general caster's rays
            // of the slab on the box excepted).
            if name == "slab on the box" {
                // (Its top face's rays, in every view that sees it.)
                if yaw == 0.0 {
                    assert!(on_st.point_evals + on_st.grad_evals > 0, "{on_st:?}");
                }
            } else {
                assert!(
                    on_st.exact_rays as usize >= hits,
                    "{name} yaw {yaw}: {on_st:?}"
                );
                assert_eq!(
                    (on_st.point_evals, on_st.grad_evals),
                    (0, 0),
                    "{name} yaw {yaw}: {on_st:?}, without: {off_st:?}"
                );
            }
        }
    }
    // Not set expressions over quadrics: a blend, a cube of the point, a
    // sine: cast the general way.
    for body in [
        "my_model = hfBlendInt(0.5 - x[1]^2 - x[2]^2 - x[3]^2, x[3], 0.1, 1, 1);",
        "my_model = 0.5 - x[1]^2 - x[2]^2 - x[3]^3;",
        "my_model = (0.5 - x[1]^2 - x[2]^2 - x[3]^2) & sin(4 * x[1]);",
    ] {
        let model = Model::compile(&format!("my_model(x[3], a[1]) {{ {body} }}")).unwrap();
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let c = ModelCaster::new(&model, Inputs::default(), b);
        let hits = cast_tiled(&c, &Camera::orbit(&b, 0.0, 90.0, None), 48, 48, 16);
        assert!(hits.hit_count() > 100, "{body}");
        assert!(c.stats().point_evals > 0, "{body}: {:?}", c.stats());
    }
}

/// Where a model is a set expression over quadrics, [`render_with`] solves
/// and shades each tile in closed form without hit records: the image
/// equals shading the hits of the same caster (closed form per ray), byte
/// for byte, in both projections; per tile, one interval evaluation for
/// its emptiness check and one per box face its rays can enter by, and no
/// samples. The slab whose face lies on the model
/// box's gives its tiles to the general caster, with the same image.
/// Tiles 16 wide, and 32 wide with a last column of 12: whole shading
/// passes (read where the solver wrote them) and partial ones, whole and
/// partial passes of ray set-up.
#[test]
fn closed_form_tiles_equal_shaded_hits() {
    for (name, src, b) in set_expression_models() {
        if name == "parameter" {
            continue;
        }
        let model = Model::compile(&src).unwrap();
        for ((yaw, pitch, fov), (w, h, tile)) in CSG_VIEWS
            .into_iter()
            .flat_map(|v| [(v, (80, 70, 16)), (v, (76, 70, 32))])
        {
            let s = RenderSettings {
                yaw,
                pitch,
                fov,
                tile_size: tile,
                ..settings(b, w, h)
            };
            let cam = s.camera();
            let c = ModelCaster::new(&model, Inputs::default(), b);
            let img =
                frep_render::render_with(&c, &s, &cam, &CancelToken::new(), &ImagePool::default())
                    .unwrap();
            let st = c.stats();
            let c2 = ModelCaster::new(&model, Inputs::default(), b);
            let hits = cast_tiled(&c2, &cam, w, h, tile);
            assert!(hits.hit_count() > 100, "{name} yaw {yaw}");
            let whole = shade(&hits, &s.lighting);
            assert_eq!(img.rgba, whole.rgba, "{name} yaw {yaw} tile {tile}");
            if name != "slab on the box" {
                // Per tile, its emptiness check and one per box face its
                // rays can enter by (at most three).
                let tiles = w.div_ceil(tile) as u64 * h.div_ceil(tile) as u64;
                assert!(
                    (tiles..=4 * tiles).contains(&st.interval_evals),
                    "{name} yaw {yaw}: {st:?}"
                );
                assert_eq!((st.point_evals, st.grad_evals), (0, 0), "{st:?}");
            }
        }
    }
}

/// Fused closed-form tiles where rays start inside the model box (the eye
/// inside it, or an orthographic view whose rays start inside it), inside
/// the solid or not: the rays' starts are no box face, so hits there must
/// not be ruled out by the box faces' intervals; the image equals shading
/// the per-ray hits, byte for byte.
#[test]
fn closed_form_tiles_with_rays_starting_in_the_box() {
    use frep_render::Projection;
    let src = "my_model(x[3], a[1]) { my_model = (0.8 - x[1]^2 - x[2]^2 - x[3]^2) \\ \
               (0.1 - x[1]^2 - x[2]^2); }";
    let model = Model::compile(src).unwrap();
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    let persp = Projection::Perspective { fov_deg: 70.0 };
    let ortho = Projection::Orthographic { half_extent: 1.2 };
    // (One thread: the tiles the general caster takes over may otherwise
    // differ in their last bits with the order of the tiles.)
    let one = pool(1);
    for (eye, target, projection) in [
        // Inside the solid, and inside the hole through it.
        ([0.0, -0.6, 0.2], [0.0, 1.0, 0.0], persp),
        ([0.0, 0.0, 0.5], [0.3, 0.0, -1.0], persp),
        // Outside the solid, in a corner of the box.
        ([0.9, 0.9, 0.9], [0.0; 3], persp),
        // Orthographic rays starting on a plane through the solid.
        ([0.0, 0.0, 0.3], [0.0, 0.0, -1.0], ortho),
    ] {
        let cam = Camera::look_at(eye, target, [0.3, 1.0, 0.2], projection);
        let s = settings(b, 64, 48);
        let c = ModelCaster::new(&model, Inputs::default(), b);
        let img = one.install(|| {
            frep_render::render_with(&c, &s, &cam, &CancelToken::new(), &ImagePool::default())
                .unwrap()
        });
        let c2 = ModelCaster::new(&model, Inputs::default(), b);
        let hits = one.install(|| cast_tiled(&c2, &cam, 64, 48, 16));
        assert!(hits.hit_count() > 100, "eye {eye:?}");
        assert_eq!(img.rgba, shade(&hits, &s.lighting).rgba, "eye {eye:?}");
        // Some tiles are solved in closed form.
        assert!(c.stats().exact_rays > 0, "eye {eye:?}: {:?}", c.stats());
    }
}

/// One caster serves views one after another (its working arrays kept
/// from one to the next): an orthographic render, whose rays share a
/// direction, leaves nothing behind for the perspective views after it,
/// per-ray closed form (`cast_tiled`) or fused tiles (`render_with`).
#[test]
fn a_caster_carries_nothing_from_view_to_view() {
    let src = example("semi_sphere.hf");
    let model = Model::compile(&src).unwrap();
    let b = bounds_of(&src);
    let top = RenderSettings {
        yaw: 0.0,
        pitch: 90.0,
        fov: None,
        ..settings(b, 64, 64)
    };
    let turn = RenderSettings {
        yaw: 30.0,
        pitch: 20.0,
        fov: Some(30.0),
        ..settings(b, 64, 64)
    };
    let shared = ModelCaster::new(&model, Inputs::default(), b);
    let fresh = || ModelCaster::new(&model, Inputs::default(), b);
    // (One thread: tiles the general caster takes over may otherwise
    // differ in their last bits with the order of the tiles.)
    let one = pool(1);
    one.install(|| {
        for (first, then) in [(&top, &turn), (&turn, &top)] {
            let _ = frep_render::render_with(
                &shared,
                first,
                &first.camera(),
                &CancelToken::new(),
                &ImagePool::default(),
            )
            .unwrap();
            let cam = then.camera();
            let hits = cast_tiled(&shared, &cam, 64, 64, 16);
            assert_eq!(hits.hits, cast_tiled(&fresh(), &cam, 64, 64, 16).hits);
            let img = frep_render::render_with(
                &shared,
                then,
                &cam,
                &CancelToken::new(),
                &ImagePool::default(),
            )
            .unwrap();
            let want = frep_render::render_with(
                &fresh(),
                then,
                &cam,
                &CancelToken::new(),
                &ImagePool::default(),
            )
            .unwrap();
            assert_eq!(img.rgba, want.rgba);
        }
    });
}

/// Random set expressions over quadrics (a fixed seed): 2 to 6 leaves —
/// spheres, axis-aligned cylinders, tilted ellipsoids with cross terms,
/// planes — joined by `&`, `|`, `\`, `min` and `max`, some negated, each
/// cast in a top view and two perspective views and checked against the
/// general caster ([`against_general`]). Every model is taken as a set
/// expression (its rays solved in closed form), and in most views no ray
/// is left to the general caster.
#[test]
fn random_set_expressions_match_the_general_caster() {
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut rnd = move || {
        // xorshift64*, in [0, 1).
        seed ^= seed >> 12;
        seed ^= seed << 25;
        seed ^= seed >> 27;
        (seed.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    };
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    let (mut models, mut clean) = (0, 0);
    while models < 12 {
        let mut r = |lo: f64, hi: f64| lo + (hi - lo) * rnd();
        let leaves = 2 + (r(0.0, 5.0) as usize);
        let mut expr = String::new();
        for k in 0..leaves {
            let (cx, cy, cz) = (r(-0.5, 0.5), r(-0.5, 0.5), r(-0.5, 0.5));
            let leaf = match r(0.0, 4.0) as u32 {
                0 => format!(
                    "({} - (x[1] - {cx})^2 - (x[2] - {cy})^2 - (x[3] - {cz})^2)",
                    r(0.05, 0.4)
                ),
                1 => {
                    let axes = [["x[1]", "x[2]"], ["x[2]", "x[3]"], ["x[1]", "x[3]"]];
                    let [u, v] = axes[r(0.0, 3.0) as usize];
                    format!("({} - ({u} - {cx})^2 - ({v} - {cy})^2)", r(0.02, 0.2))
                }
                2 => format!(
                    "({} - {} * (x[1] - {cx})^2 - {} * (x[2] - {cy})^2 - {} * (x[3] - {cz})^2 - {} * x[1] * x[3] - {} * x[2] * x[3])",
                    r(0.05, 0.3),
                    r(0.5, 2.0),
                    r(0.5, 2.0),
                    r(0.5, 2.0),
                    r(-0.4, 0.4),
                    r(-0.4, 0.4)
                ),
                _ => format!(
                    "({} + {} * x[1] + {} * x[2] + {} * x[3])",
                    r(-0.3, 0.3),
                    r(-1.0, 1.0),
                    r(-1.0, 1.0),
                    r(-1.0, 1.0)
                ),
            };
            let leaf = if r(0.0, 1.0) < 0.15 {
                format!("-{leaf}")
            } else {
                leaf
            };
            expr = if k == 0 {
                leaf
            } else {
                match r(0.0, 5.0) as u32 {
                    0 => format!("({expr} & {leaf})"),
                    1 => format!("({expr} | {leaf})"),
                    2 => format!("({expr} \\ {leaf})"),
                    3 => format!("min({expr}, {leaf})"),
                    _ => format!("max({expr}, {leaf})"),
                }
            };
        }
        let src = format!("my_model(x[3], a[1]) {{ my_model = {expr}; }}");
        let model = Model::compile(&src).unwrap();
        // Too little of the solid in view for a comparison: the next one.
        let probe = cast_tiled(
            &ModelCaster::new(&model, Inputs::default(), b),
            &Camera::orbit(&b, 0.0, 90.0, None),
            32,
            32,
            16,
        );
        if !(60..=900).contains(&probe.hit_count()) {
            continue;
        }
        models += 1;
        for (yaw, pitch, fov) in [
            (0.0, 90.0, None),
            (30.0, 20.0, Some(30.0)),
            (200.0, -30.0, Some(60.0)),
        ] {
            let cam = Camera::orbit(&b, yaw, pitch, fov);
            let what = format!("{src} yaw {yaw}");
            let (on_st, _, hits) =
                against_general(&what, &model, &Inputs::default(), b, &cam, true);
            assert!(on_st.exact_rays > 0, "{what}: {on_st:?}");
            if hits > 0 && on_st.point_evals == 0 {
                clean += 1;
            }
        }
    }
    assert!(
        clean >= 24,
        "{clean} of 36 views without the general caster"
    );
}

/// A root gap `k − sqrt(p)` whose `p` is negative, its value NaN (outside),
/// in part of the box: the exact slabs, whose polynomial `k² − p` says
/// nothing of where `p < 0`, take no hit where a slab starts in that part
/// (once, a slab starting there was a hit, a few footprints in front of
/// the surface). With the closed form on set expressions off, the hits
/// are sampling's, in four views, on one thread and on two (which tile
/// fits a shortened tape's quadric first changes with the threads).
#[test]
fn root_gaps_are_not_hit_where_undefined() {
    let src = "my_model(x[3], a[1]) { my_model = (0.6 - sqrt(x[1]^2 - x[2]^2 + 0.2)) & (0.8 - x[1]^2 - x[2]^2 - x[3]^2); }";
    let model = Model::compile(src).unwrap();
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    let (w, h) = (96, 96);
    for threads in [1, 2] {
        let pool = pool(threads);
        for (yaw, pitch, fov) in CSG_VIEWS {
            let cam = Camera::orbit(&b, yaw, pitch, fov);
            let [(on, _), (off, _)] = pool.install(|| cast_exact_on_off(&model, b, &cam, w, h));
            assert!(off.hit_count() > 300, "yaw {yaw}: {} hits", off.hit_count());
            let what = format!("{threads} threads, yaw {yaw}");
            let differ = exact_agrees(&what, &cam, &on, &off);
            assert!(differ <= 3, "{what}: {differ} pixels differ");
        }
    }
}
