//! Tests of the section plane (`RenderSettings::section`): a sphere cut
//! open shows its flat face where an analytic reference says, with the
//! plane's normal and the cap colour (perspective and orthographic, planes
//! facing the camera and oblique, the closed-form paths on and off); the
//! cut face of a model with colours keeps the model's colour there; a plane
//! that removes everything leaves the background; a plane that removes
//! nothing changes nothing; bad planes are refused; a real model's hits
//! all lie on the kept side.

use frep_core::eval::batch::BatchEval;
use frep_core::eval::Inputs;
use frep_core::Model;
use frep_render::{
    render, render_hits, Aabb, Camera, CancelToken, HitBuffer, ImagePool, ModelCaster, RenderError,
    RenderSettings, Section, SECTION_CAP,
};

const SPHERE: &str = "my_model(x[3], a[1]) { my_model = 0.8 - sqrt(x[1]^2 + x[2]^2 + x[3]^2); }";
const R: f64 = 0.8;

fn example(name: &str) -> String {
    let p = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{p}: {e}"))
}

fn bounds_of(src: &str) -> Aabb {
    let line = src
        .lines()
        .find_map(|l| l.trim().strip_prefix("-- bounds:"))
        .expect("bounds line");
    let v: Vec<f64> = line.split(',').map(|s| s.trim().parse().unwrap()).collect();
    Aabb::new([v[0], v[1], v[2]], [v[3], v[4], v[5]])
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn settings(size: u32, fov: Option<f64>, section: Option<Section>) -> RenderSettings {
    RenderSettings {
        size: (size, size),
        bounds: Aabb::new([-1.0; 3], [1.0; 3]),
        fov,
        tile_size: 16,
        section,
        ..Default::default()
    }
}

/// What the ray of a pixel meets first in the sphere of radius `R` cut by
/// `s` (unit normal): `None`, or the distance and whether it is on the
/// cut face.
fn reference(o: [f64; 3], d: [f64; 3], s: &Section) -> Option<(f64, bool)> {
    let b = dot(o, d);
    let disc = b * b - (dot(o, o) - R * R);
    if disc < 0.0 {
        return None;
    }
    let (mut t0, mut t1) = (-b - disc.sqrt(), -b + disc.sqrt());
    t0 = t0.max(0.0);
    let nd = dot(s.normal, d);
    let room = s.offset - dot(s.normal, o);
    let mut cap = false;
    if nd.abs() < 1e-15 {
        if room < 0.0 {
            return None;
        }
    } else if nd > 0.0 {
        t1 = t1.min(room / nd);
    } else if room / nd > t0 {
        t0 = room / nd;
        cap = true;
    }
    (t0 <= t1).then_some((t0, cap))
}

/// Every pixel of `hits` against [`reference`]: the same hit or miss
/// except on the reference's own boundary (a neighbour differs), hits
/// within two footprints of the reference's depth, cut-face hits with the
/// plane's normal and the cap colour, other hits with the sphere's normal
/// and no colour. Returns how many pixels are on the cut face.
fn check_against_reference(cam: &Camera, hits: &HitBuffer, s: &Section) -> usize {
    let (w, h) = (hits.width, hits.height);
    let rm = cam.rays(w, h);
    let refs: Vec<Option<(f64, bool)>> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let r = rm.ray(x, y);
            reference(r.origin, r.dir, s)
        })
        .collect();
    let at = |x: i64, y: i64| -> Option<Option<(f64, bool)>> {
        (x >= 0 && y >= 0 && x < w as i64 && y < h as i64)
            .then(|| refs[(y * w as i64 + x) as usize])
    };
    let (mut caps, mut mismatches, mut hit_count) = (0, 0, 0);
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let want = refs[(y * w as i64 + x) as usize];
            let got = &hits.hits[(y * w as i64 + x) as usize];
            // On the boundary: a neighbour differs in hit or face.
            let edge = (-1..=1).any(|dy| {
                (-1..=1).any(|dx| {
                    at(x + dx, y + dy).is_some_and(|n| n.map(|v| v.1) != want.map(|v| v.1))
                })
            });
            hit_count += usize::from(want.is_some());
            match (want, got) {
                (Some((t, cap)), Some(g)) => {
                    let fp = cam.pixel_footprint(t, w, h);
                    assert!(
                        (g.t - t).abs() <= 2.0 * fp,
                        "pixel ({x}, {y}): t {} vs {t}",
                        g.t
                    );
                    if edge {
                        continue;
                    }
                    let n = unit(g.normal);
                    if cap {
                        caps += 1;
                        assert!(dot(n, s.normal) > 1.0 - 1e-9, "({x}, {y}) normal {n:?}");
                        assert_eq!(g.color, Some(SECTION_CAP), "({x}, {y})");
                    } else {
                        let sphere = unit(g.position);
                        assert!(dot(n, sphere) > 0.999, "({x}, {y}) normal {n:?}");
                        assert_eq!(g.color, None, "({x}, {y})");
                    }
                }
                (None, None) => {}
                _ => {
                    assert!(edge, "pixel ({x}, {y}): got {got:?}, want {want:?}");
                    mismatches += 1;
                }
            }
        }
    }
    assert!(
        mismatches * 50 <= hit_count.max(1),
        "{mismatches} boundary mismatches of {hit_count} hits"
    );
    caps
}

/// A sphere cut in half: the cut face is where the analytic reference
/// puts it, flat (the plane's normal) and in the cap colour, for planes
/// through the centre facing the camera, oblique and seen edge-on, in
/// perspective and orthographic views, with the closed-form paths on and
/// off.
#[test]
fn sphere_cut_in_half_shows_its_flat_face() {
    let model = Model::compile(SPHERE).unwrap();
    for fov in [Some(30.0), None] {
        let base = settings(96, fov, None);
        let cam = base.camera();
        let to_eye = unit(cam.eye);
        let planes = [
            (to_eye, 0.0, true),
            (unit([1.0, -0.4, 0.3]), 0.2, true),
            (unit([-to_eye[0], -to_eye[1], -to_eye[2]]), 0.1, false),
        ];
        for (normal, offset, faces_camera) in planes {
            let s = Section { normal, offset };
            let set = RenderSettings {
                section: Some(s),
                ..base.clone()
            };
            for closed in [true, false] {
                let mut caster =
                    ModelCaster::sectioned(&model, Inputs::default(), set.bounds, Some(&s))
                        .unwrap();
                caster.csg = closed;
                caster.exact = closed;
                let hits = frep_render::cast_tiled(&caster, &cam, 96, 96, 16);
                let caps = check_against_reference(&cam, &hits, &s);
                // The sphere and the plane are a set expression over
                // quadrics: solved in closed form where allowed.
                assert_eq!(caster.stats().exact_rays > 0, closed);
                if faces_camera {
                    assert!(caps > 500, "{caps} cut-face pixels ({fov:?}, {normal:?})");
                } else {
                    assert_eq!(caps, 0, "the face turned away is not seen");
                }
            }
            // The public path agrees.
            let hits = render_hits(&model, &set, &CancelToken::new()).unwrap();
            check_against_reference(&cam, &hits, &s);
        }
    }
}

/// The shaded image: the centre of a sphere cut facing the camera is the
/// cap's colour (orange), the uncut sphere's is grey; the corners are the
/// same background.
#[test]
fn cut_face_is_shaded_in_the_cap_colour() {
    let model = Model::compile(SPHERE).unwrap();
    let plain = settings(64, Some(30.0), None);
    let to_eye = unit(plain.camera().eye);
    let cut = RenderSettings {
        section: Some(Section {
            normal: to_eye,
            offset: 0.0,
        }),
        ..plain.clone()
    };
    let a = render(&model, &plain, &CancelToken::new(), &ImagePool::default()).unwrap();
    let b = render(&model, &cut, &CancelToken::new(), &ImagePool::default()).unwrap();
    let px = |img: &frep_render::Image, x: u32, y: u32| {
        let i = ((y * img.width + x) * 4) as usize;
        [img.rgba[i], img.rgba[i + 1], img.rgba[i + 2]].map(i32::from)
    };
    let (g, o) = (px(&a, 32, 32), px(&b, 32, 32));
    assert!((g[0] - g[2]).abs() < 30, "uncut centre is grey: {g:?}");
    assert!(
        o[0] > o[1] + 40 && o[1] > o[2] + 20,
        "cut centre is orange: {o:?}"
    );
    assert_eq!(px(&a, 0, 0), px(&b, 0, 0));
    assert_eq!(px(&a, 63, 63), px(&b, 63, 63));
}

/// A plane that keeps nothing of the model box leaves only the background:
/// no hit, and the image of a model that is nowhere inside.
#[test]
fn plane_removing_everything_gives_the_background() {
    let model = Model::compile(SPHERE).unwrap();
    let empty = Model::compile("my_model(x[3], a[1]) { my_model = -1; }").unwrap();
    for normal in [[0.0, 0.0, 1.0], unit([0.3, 0.5, -0.8])] {
        let s = settings(
            48,
            Some(30.0),
            Some(Section {
                normal,
                offset: -2.0,
            }),
        );
        let hits = render_hits(&model, &s, &CancelToken::new()).unwrap();
        assert!(hits.hits.iter().all(|h| h.is_none()));
        let img = render(&model, &s, &CancelToken::new(), &ImagePool::default()).unwrap();
        let bg = render(
            &empty,
            &settings(48, Some(30.0), None),
            &CancelToken::new(),
            &ImagePool::default(),
        )
        .unwrap();
        assert_eq!(img.rgba, bg.rgba);
    }
}

/// A plane beyond the model box removes nothing: the same image as no
/// plane at all, bit for bit, for a model with colours too.
#[test]
fn plane_removing_nothing_changes_nothing() {
    for src in [SPHERE.to_string(), example("sake_pot.hf")] {
        let model = Model::compile(&src).unwrap();
        let bounds = if src == SPHERE {
            Aabb::new([-1.0; 3], [1.0; 3])
        } else {
            bounds_of(&src)
        };
        let plain = RenderSettings {
            bounds,
            ..settings(64, Some(30.0), None)
        };
        let far = RenderSettings {
            section: Some(Section {
                normal: unit([0.2, -0.9, 0.4]),
                offset: 10.0,
            }),
            ..plain.clone()
        };
        let a = render(&model, &plain, &CancelToken::new(), &ImagePool::default()).unwrap();
        let b = render(&model, &far, &CancelToken::new(), &ImagePool::default()).unwrap();
        let differ = a.rgba.iter().zip(&b.rgba).filter(|(x, y)| x != y).count();
        // (The sectioned tape differs until the interval pruning drops the
        // plane: a few bits of a normal may round differently.)
        assert!(differ * 1000 <= a.rgba.len(), "{differ} bytes differ");
        let ha = render_hits(&model, &plain, &CancelToken::new()).unwrap();
        let hb = render_hits(&model, &far, &CancelToken::new()).unwrap();
        let mask = |h: &HitBuffer| h.hits.iter().map(Option::is_some).collect::<Vec<_>>();
        assert_eq!(mask(&ha), mask(&hb));
    }
}

/// A normal that is zero or not finite is refused with an error, not a
/// panic; a normal of any length is the same plane as its unit one.
#[test]
fn bad_planes_are_refused() {
    let model = Model::compile(SPHERE).unwrap();
    for (normal, offset) in [
        ([0.0; 3], 0.0),
        ([f64::NAN, 0.0, 1.0], 0.0),
        ([0.0, 1.0, 0.0], f64::INFINITY),
    ] {
        let s = settings(16, Some(30.0), Some(Section { normal, offset }));
        assert!(matches!(
            render(&model, &s, &CancelToken::new(), &ImagePool::default()),
            Err(RenderError::BadSection(_))
        ));
        assert!(matches!(
            render_hits(&model, &s, &CancelToken::new()),
            Err(RenderError::BadSection(_))
        ));
    }
    let long = settings(
        32,
        Some(30.0),
        Some(Section {
            normal: [0.0, 0.0, 4.0],
            offset: 1.0,
        }),
    );
    let short = settings(
        32,
        Some(30.0),
        Some(Section {
            normal: [0.0, 0.0, 1.0],
            offset: 0.25,
        }),
    );
    assert_eq!(
        render(&model, &long, &CancelToken::new(), &ImagePool::default())
            .unwrap()
            .rgba,
        render(&model, &short, &CancelToken::new(), &ImagePool::default())
            .unwrap()
            .rgba
    );
}

/// The sake pot (a hollow bottle with a cobalt band) cut through its axis:
/// every hit is on the kept side and inside or on the model; the cut face
/// is seen (hits on the plane with its normal), inside the wall only, and
/// keeps the model's attribute colour there.
#[test]
fn sake_pot_cut_through_its_axis() {
    let src = example("sake_pot.hf");
    let model = Model::compile(&src).unwrap();
    let bounds = bounds_of(&src);
    let base = RenderSettings {
        bounds,
        ..settings(96, Some(30.0), None)
    };
    let cam = base.camera();
    // A vertical plane through the axis, turned towards the camera.
    let normal = unit([cam.eye[0], cam.eye[1], 0.0]);
    let s = Section {
        normal,
        offset: 0.0,
    };
    let set = RenderSettings {
        section: Some(s),
        ..base
    };
    let hits = render_hits(&model, &set, &CancelToken::new()).unwrap();
    let mut ev = BatchEval::new(&model.tape());
    let attrs = model.attribute_tape().expect("the pot has colours");
    let mut av = BatchEval::new(&attrs);
    let inputs = Inputs::default();
    let (mut caps, mut all) = (0, 0);
    for h in hits.hits.iter().flatten() {
        all += 1;
        let fp = cam.pixel_footprint(h.t, 96, 96);
        assert!(
            s.signed(h.position) >= -2.0 * fp,
            "{:?} on the cut side",
            h.position
        );
        let on_plane = s.signed(h.position).abs() <= fp;
        let n = unit(h.normal);
        if !(on_plane && dot(n, normal) > 1.0 - 1e-9) {
            continue;
        }
        caps += 1;
        let [x, y, z] = h.position;
        let mut v = [0.0];
        ev.eval(&[x], &[y], &[z], &inputs, &mut v);
        assert!(
            v[0] >= -1e-6,
            "cut face at {:?} is inside the model ({})",
            h.position,
            v[0]
        );
        let mut c = vec![Vec::new(); attrs.outputs.len()];
        av.eval_outputs(&[x], &[y], &[z], &inputs, &mut c);
        let want = [c[0][0], c[1][0], c[2][0]].map(|v| v.clamp(0.0, 1.0) as f32);
        let got = h.color.expect("a colour on the cut face");
        for k in 0..3 {
            assert!((got[k] - want[k]).abs() < 1e-3, "{got:?} vs {want:?}");
        }
    }
    assert!(caps > 100 && caps < all, "{caps} cut-face hits of {all}");
}
