//! Tests of the library port: golden values of the reference interpreter,
//! independent f64 formulas, quadrature of the convolution kernels, and
//! symbolic builds evaluated against constant ones.

#![allow(
    clippy::excessive_precision,
    clippy::approx_constant,
    clippy::type_complexity
)]

use super::*;
use crate::graph::Node;
use crate::ops;

/// A test argument.
#[derive(Clone)]
enum Ta {
    S(f64),
    A(Vec<f64>),
}
use Ta::{A as Arr, S as Sc};

fn arr(v: &[f64]) -> Ta {
    Arr(v.to_vec())
}

fn to_args(g: &mut Graph, ta: &[Ta]) -> Vec<LibArg> {
    ta.iter()
        .map(|t| match t {
            Sc(v) => LibArg::Scalar(g.constant(*v)),
            Arr(v) => LibArg::Array(v.iter().map(|&x| g.constant(x)).collect()),
        })
        .collect()
}

fn consts(g: &Graph, v: &[NodeId]) -> Vec<f64> {
    v.iter()
        .map(|&n| g.const_value(n).expect("constant item"))
        .collect()
}

/// Calls `name` with constant arguments: its value and the final arrays.
fn run(name: &str, ta: &[Ta]) -> (f64, Vec<Vec<f64>>) {
    let f = lookup(name).unwrap_or_else(|| panic!("{name} missing"));
    assert_eq!(f.params.len(), ta.len(), "{name} arity");
    let mut g = Graph::new();
    let mut args = to_args(&mut g, ta);
    let r = (f.build)(&mut g, &mut args).unwrap_or_else(|e| panic!("{name}: {e}"));
    let v = g
        .const_value(r)
        .unwrap_or_else(|| panic!("{name} did not fold"));
    let arrays = args
        .iter()
        .map(|a| match a {
            LibArg::Array(v) => consts(&g, v),
            LibArg::Scalar(_) => Vec::new(),
        })
        .collect();
    (v, arrays)
}

fn val(name: &str, ta: &[Ta]) -> f64 {
    run(name, ta).0
}

fn run_err(name: &str, ta: &[Ta]) -> LibError {
    let f = lookup(name).unwrap();
    let mut g = Graph::new();
    let mut args = to_args(&mut g, ta);
    (f.build)(&mut g, &mut args).expect_err("expected a LibError")
}

fn close(got: f64, want: f64, rel: f64, abs: f64) -> bool {
    (got.is_nan() && want.is_nan()) || got == want || (got - want).abs() <= abs + rel * want.abs()
}

#[track_caller]
fn assert_close(got: f64, want: f64) {
    assert!(close(got, want, 1e-12, 1e-14), "got {got:e}, want {want:e}");
}

// ---------------------------------------------------------------------------
// Golden values

fn golden(model: &str) -> Vec<([f64; 3], f64)> {
    let path = format!(
        "{}/tests/data/golden/{model}.txt",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let (pt, v) = line.split_once('|').expect("golden line");
        let v = v.trim();
        if v.starts_with("error") {
            continue;
        }
        let p: Vec<f64> = pt.split_whitespace().map(|s| s.parse().unwrap()).collect();
        let f: f64 = v.split_whitespace().next().unwrap().parse().unwrap();
        out.push(([p[0], p[1], p[2]], f));
    }
    assert!(out.len() >= 40, "{model}: {} points", out.len());
    out
}

/// Compares `f` with the golden values of `model` to 1e-9 relative / 1e-12
/// absolute; returns how many were bit-exact.
fn check_golden(model: &str, f: impl Fn([f64; 3]) -> f64) -> usize {
    let mut exact = 0;
    let pts = golden(model);
    for &(p, want) in &pts {
        let got = f(p);
        assert!(
            close(got, want, 1e-9, 1e-12),
            "{model} at {p:?}: got {got:?}, want {want:?}"
        );
        if got.to_bits() == want.to_bits() {
            exact += 1;
        }
    }
    eprintln!("{model}: {exact}/{} bit-exact", pts.len());
    exact
}

fn transform(p: [f64; 3], name: &str, rest: &[Ta]) -> Vec<f64> {
    let mut ta = vec![arr(&p)];
    ta.extend_from_slice(rest);
    let (r, arrays) = run(name, &ta);
    assert_eq!(r, 1.0);
    arrays[0].clone()
}

#[test]
fn golden_primitives() {
    let mut total = 0;
    let c = |v: &[f64]| arr(v);
    let p = |p: [f64; 3]| arr(&p);
    total += check_golden("prim_sphere", |x| {
        val("hfsphere", &[p(x), c(&[0.1, -0.2, 0.3]), Sc(1.5)])
    });
    total += check_golden("prim_ellipsoid", |x| {
        val(
            "hfellipsoid",
            &[p(x), c(&[0.2, 0.1, -0.1]), Sc(1.2), Sc(0.8), Sc(0.5)],
        )
    });
    for (ax, name) in ["X", "Y", "Z"]
        .iter()
        .zip(["hfcylinderx", "hfcylindery", "hfcylinderz"])
    {
        total += check_golden(&format!("prim_cylinder{ax}"), |x| {
            val(name, &[p(x), c(&[0.3, -0.4, 0.5]), Sc(0.7)])
        });
    }
    for (ax, name) in ["X", "Y", "Z"]
        .iter()
        .zip(["hfellcylx", "hfellcyly", "hfellcylz"])
    {
        total += check_golden(&format!("prim_ellcyl{ax}"), |x| {
            val(name, &[p(x), c(&[-0.3, 0.2, 0.1]), Sc(0.6), Sc(1.1)])
        });
    }
    for (ax, name) in ["X", "Y", "Z"]
        .iter()
        .zip(["hfconex", "hfconey", "hfconez"])
    {
        total += check_golden(&format!("prim_cone{ax}"), |x| {
            val(name, &[p(x), c(&[0.1, 0.2, -0.3]), Sc(0.5)])
        });
    }
    for (ax, name) in ["X", "Y", "Z"]
        .iter()
        .zip(["hfellconex", "hfellconey", "hfellconez"])
    {
        total += check_golden(&format!("prim_ellcone{ax}"), |x| {
            val(name, &[p(x), c(&[0.0, 0.25, 0.5]), Sc(0.4), Sc(0.9)])
        });
    }
    for (ax, name) in ["X", "Y", "Z"]
        .iter()
        .zip(["hftorusx", "hftorusy", "hftorusz"])
    {
        total += check_golden(&format!("prim_torus{ax}"), |x| {
            val(name, &[p(x), c(&[0.1, -0.1, 0.2]), Sc(1.2), Sc(0.35)])
        });
    }
    total += check_golden("prim_block", |x| {
        val(
            "hfblock",
            &[p(x), c(&[-0.5, -0.75, -1.0]), Sc(1.0), Sc(1.5), Sc(2.0)],
        )
    });
    total += check_golden("prim_superell", |x| {
        val(
            "hfsuperell",
            &[
                p(x),
                c(&[0.0, 0.1, 0.0]),
                Sc(1.0),
                Sc(0.8),
                Sc(0.6),
                Sc(0.5),
                Sc(1.5),
            ],
        )
    });
    total += check_golden("prim_blobby", |x| {
        val(
            "hfblobby",
            &[
                p(x),
                c(&[-0.5, 0.5, 0.0]),
                c(&[0.0, 0.0, 0.6]),
                c(&[0.0, 0.1, -0.2]),
                c(&[2.0, 3.0, 2.5]),
                c(&[1.0, 1.2, 0.8]),
                Sc(0.4),
            ],
        )
    });
    total += check_golden("prim_metaball", |x| {
        val(
            "hfmetaball",
            &[
                p(x),
                c(&[-0.5, 0.5, 0.0]),
                c(&[0.0, 0.0, 0.6]),
                c(&[0.0, 0.1, -0.2]),
                c(&[1.0, 1.5, 0.8]),
                c(&[1.5, 1.2, 2.0]),
                Sc(0.3),
            ],
        )
    });
    total += check_golden("prim_soft", |x| {
        val(
            "hfsoft",
            &[
                p(x),
                c(&[-0.4, 0.4]),
                c(&[0.0, 0.2]),
                c(&[0.1, -0.1]),
                c(&[1.2, 1.5]),
                Sc(0.2),
            ],
        )
    });
    total += check_golden("prim_convpoint", |x| {
        val(
            "hfconvpoint",
            &[
                p(x),
                c(&[-0.5, 0.0, 0.0, 0.5, 0.2, 0.1]),
                c(&[1.5, 2.0]),
                Sc(0.3),
            ],
        )
    });
    total += check_golden("prim_convline", |x| {
        val(
            "hfconvline",
            &[
                p(x),
                c(&[-1.0, 0.0, 0.0, 0.0, -1.0, 0.2]),
                c(&[1.0, 0.0, 0.0, 0.0, 1.0, -0.2]),
                c(&[2.0, 1.5]),
                Sc(0.5),
            ],
        )
    });
    total += check_golden("prim_convcurve", |x| {
        val(
            "hfconvcurve",
            &[
                p(x),
                c(&[
                    -1.0, 0.0, 0.0, -0.3, 0.5, 0.0, 0.3, -0.5, 0.1, 1.0, 0.0, 0.0,
                ]),
                c(&[2.0, 2.0, 2.0]),
                Sc(0.5),
            ],
        )
    });
    total += check_golden("prim_noiseg", |x| {
        let e = val(
            "hfellipsoid",
            &[p(x), c(&[0.0; 3]), Sc(1.2), Sc(0.9), Sc(0.7)],
        );
        let n = val("hfnoiseg", &[p(x), Sc(0.3), Sc(5.0), Sc(1.2)]);
        e + n
    });
    eprintln!("primitives: {total} bit-exact values");
}

#[test]
fn golden_operations() {
    let p = |p: [f64; 3]| arr(&p);
    check_golden("op_blenduni", |x| {
        let f1 = val("hfsphere", &[p(x), arr(&[-0.6, 0.0, 0.0]), Sc(0.7)]);
        let f2 = val("hfsphere", &[p(x), arr(&[0.6, 0.1, 0.0]), Sc(0.6)]);
        val("hfblenduni", &[Sc(f1), Sc(f2), Sc(0.5), Sc(0.4), Sc(0.4)])
    });
    check_golden("op_blendint", |x| {
        let f1 = val("hfsphere", &[p(x), arr(&[-0.3, 0.0, 0.0]), Sc(0.9)]);
        let f2 = val("hfsphere", &[p(x), arr(&[0.3, 0.1, 0.0]), Sc(0.8)]);
        val("hfblendint", &[Sc(f1), Sc(f2), Sc(0.3), Sc(0.5), Sc(0.5)])
    });
    // SPEC §7
    let f1 = val("hfsphere", &[arr(&[0.0; 3]), arr(&[0.0; 3]), Sc(1.0)]);
    let f2 = val("hfsphere", &[arr(&[0.0; 3]), arr(&[0.0; 3]), Sc(2.0)]);
    let b = val("hfblenduni", &[Sc(f1), Sc(f2), Sc(1.0), Sc(0.0), Sc(1.0)]);
    assert_eq!(b, 9.1231056256176615);
    let f1 = val(
        "hfsphere",
        &[arr(&[0.0, 0.0, 1.0]), arr(&[0.0; 3]), Sc(1.0)],
    );
    let f2 = val(
        "hfsphere",
        &[arr(&[0.0, 0.0, 1.0]), arr(&[0.0; 3]), Sc(2.0)],
    );
    let b = val("hfblenduni", &[Sc(f1), Sc(f2), Sc(1.0), Sc(0.0), Sc(1.0)]);
    assert!(b.is_nan());
}

#[test]
fn golden_transformations() {
    let zero = arr(&[0.0; 3]);
    let sphere = |xt: Vec<f64>| val("hfsphere", &[Arr(xt), arr(&[0.0; 3]), Sc(1.0)]);
    let ellipsoid = |xt: Vec<f64>| {
        val(
            "hfellipsoid",
            &[Arr(xt), arr(&[0.0; 3]), Sc(1.5), Sc(0.7), Sc(0.4)],
        )
    };
    for (ax, name) in ["X", "Y", "Z"]
        .iter()
        .zip(["hfrotate3dx", "hfrotate3dy", "hfrotate3dz"])
    {
        check_golden(&format!("xf_rotate3d{ax}"), |x| {
            ellipsoid(transform(x, name, &[Sc(0.6)]))
        });
    }
    check_golden("xf_scale_shift", |x| {
        let xt = transform(x, "hfshift3d", &[Sc(0.3), Sc(-0.2), Sc(0.1)]);
        let xt = transform(
            [xt[0], xt[1], xt[2]],
            "hfscale3d",
            &[Sc(1.5), Sc(0.8), Sc(1.2)],
        );
        val("hftorusz", &[Arr(xt), zero.clone(), Sc(0.8), Sc(0.25)])
    });
    let sm = [
        arr(&[0.0, 0.0, 1.0]),
        arr(&[0.0, 0.0, 1.5]),
        arr(&[0.5, 0.5, 0.7]),
    ];
    check_golden("xf_spacemap", |x| {
        sphere(transform(x, "hfspacemapexp", &sm))
    });
    check_golden("xf_spacemapcubic", |x| {
        sphere(transform(x, "hfspacemapcubic", &sm))
    });
    check_golden("xf_stretch", |x| {
        sphere(transform(
            x,
            "hfstretch3d",
            &[arr(&[0.2, 0.0, -0.1]), Sc(1.5), Sc(0.7), Sc(1.1)],
        ))
    });
    for (ax, name) in ["X", "Y", "Z"]
        .iter()
        .zip(["hftaperx", "hftapery", "hftaperz"])
    {
        check_golden(&format!("xf_taper{ax}"), |x| {
            sphere(transform(x, name, &[Sc(-1.0), Sc(1.0), Sc(0.5), Sc(1.5)]))
        });
    }
    for (ax, name) in ["X", "Y", "Z"]
        .iter()
        .zip(["hftwistx", "hftwisty", "hftwistz"])
    {
        check_golden(&format!("xf_twist{ax}"), |x| {
            let xt = transform(x, name, &[Sc(-1.5), Sc(1.5), Sc(0.0), Sc(1.57)]);
            val(
                "hfblock",
                &[Arr(xt), arr(&[-0.5, -0.5, -1.5]), Sc(1.0), Sc(1.0), Sc(3.0)],
            )
        });
    }
    // SPEC §7: hfScale3D(x,2,2,2) then x[1] at x=4 -> 2
    assert_eq!(
        transform([4.0, 0.0, 0.0], "hfscale3d", &[Sc(2.0), Sc(2.0), Sc(2.0)])[0],
        2.0
    );
}

// ---------------------------------------------------------------------------
// Independent formulas

const PTS: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [0.3, -0.7, 1.1],
    [-1.2, 0.4, 0.25],
    [2.0, 1.5, -0.5],
    [0.05, 0.9, -1.3],
];

fn sq(v: f64) -> f64 {
    v * v
}

#[test]
fn simple_primitives_match_spec_formulas() {
    let c = [0.2, -0.3, 0.4];
    for x in PTS {
        let (dx, dy, dz) = (x[0] - c[0], x[1] - c[1], x[2] - c[2]);
        let xa = arr(&x);
        let ca = arr(&c);
        assert_close(
            val("hfsphere", &[xa.clone(), ca.clone(), Sc(1.3)]),
            1.69 - dx * dx - dy * dy - dz * dz,
        );
        assert_close(
            val(
                "hfellipsoid",
                &[xa.clone(), ca.clone(), Sc(1.1), Sc(0.7), Sc(0.5)],
            ),
            1.0 - sq(dx / 1.1) - sq(dy / 0.7) - sq(dz / 0.5),
        );
        let d = [dx, dy, dz];
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            let (i, j) = other_axes(k);
            assert_close(
                val(
                    &format!("hfcylinder{axis}"),
                    &[xa.clone(), ca.clone(), Sc(0.8)],
                ),
                0.64 - d[i] * d[i] - d[j] * d[j],
            );
            assert_close(
                val(
                    &format!("hfellcyl{axis}"),
                    &[xa.clone(), ca.clone(), Sc(0.8), Sc(1.6)],
                ),
                1.0 - sq(d[i] / 0.8) - sq(d[j] / 1.6),
            );
            assert_close(
                val(&format!("hfcone{axis}"), &[xa.clone(), ca.clone(), Sc(0.6)]),
                d[k] * d[k] - sq(d[i] / 0.6) - sq(d[j] / 0.6),
            );
            assert_close(
                val(
                    &format!("hfellcone{axis}"),
                    &[xa.clone(), ca.clone(), Sc(0.6), Sc(0.9)],
                ),
                d[k] * d[k] - sq(d[i] / 0.6) - sq(d[j] / 0.9),
            );
            let (big, r0) = (1.2, 0.35);
            let rho = (d[i] * d[i] + d[j] * d[j]).sqrt();
            assert_close(
                val(
                    &format!("hftorus{axis}"),
                    &[xa.clone(), ca.clone(), Sc(big), Sc(r0)],
                ),
                r0 * r0 - dx * dx - dy * dy - dz * dz - big * big + 2.0 * big * rho,
            );
            // distance variants
            let t = 0.6f64.atan();
            assert_close(
                val(
                    &format!("hfdcone{axis}"),
                    &[xa.clone(), ca.clone(), Sc(0.6)],
                ),
                -(rho * t.cos() - d[k].abs() * t.sin()),
            );
            assert_close(
                val(
                    &format!("hfdtorus{axis}"),
                    &[xa.clone(), ca.clone(), Sc(big), Sc(r0)],
                ),
                -(((rho - big).powi(2) + d[k] * d[k]).sqrt() - r0),
            );
        }
        // hfDCylinder: R - distance to the axis line through c along u.
        let u = [0.3, 0.5, -0.2];
        let (cx, cy, cz) = (
            u[1] * (-dz) - u[2] * (-dy),
            u[2] * (-dx) - u[0] * (-dz),
            u[0] * (-dy) - u[1] * (-dx),
        );
        let dist =
            ((cx * cx + cy * cy + cz * cz) / (u[0] * u[0] + u[1] * u[1] + u[2] * u[2])).sqrt();
        assert_close(
            val("hfdcylinder", &[xa.clone(), ca.clone(), arr(&u), Sc(0.9)]),
            0.9 - dist,
        );
        // block with v = c as the min corner
        let (ddx, ddy, ddz) = (1.0, 1.5, 0.7);
        let u = dx * (ddx - dx);
        let w = dy * (ddy - dy);
        let t = dz * (ddz - dz);
        let f = ops::r_inter(ops::r_inter(u, w), t);
        assert_close(
            val(
                "hfblock",
                &[xa.clone(), ca.clone(), Sc(ddx), Sc(ddy), Sc(ddz)],
            ),
            f,
        );
        // superellipsoid
        let (a, b, cc, s1, s2) = (1.0, 0.8, 0.6, 0.5, 1.5);
        let want = 1.0
            - ((dx / a).abs().powf(2.0 / s2) + (dy / b).abs().powf(2.0 / s2)).powf(s2 / s1)
            - (dz / cc).abs().powf(2.0 / s1);
        assert_close(
            val(
                "hfsuperell",
                &[xa.clone(), ca.clone(), Sc(a), Sc(b), Sc(cc), Sc(s1), Sc(s2)],
            ),
            want,
        );
        // noise
        let (amp, freq, ph) = (0.5, 4.0, 1.4);
        let s = [
            (freq * x[0]).sin(),
            (freq * x[1]).sin(),
            (freq * x[2]).sin(),
        ];
        let k = amp / 1.17;
        let sx = amp * s[0] + k * (freq * x[0] / 1.35 + ph * s[2]).sin();
        let sy = amp * s[1] + k * (freq * x[1] / 1.35 + ph * s[0]).sin();
        let sz = amp * s[2] + k * (freq * x[2] / 1.35 + ph * s[1]).sin();
        assert_close(
            val("hfnoiseg", &[xa.clone(), Sc(amp), Sc(freq), Sc(ph)]),
            sx * sy * sz,
        );
    }
}

#[test]
fn sentinels() {
    let x2 = arr(&[0.0, 0.0]);
    let c = arr(&[0.0; 3]);
    for name in ["hfsphere", "hfcylinderx", "hfconez"] {
        assert_eq!(val(name, &[x2.clone(), c.clone(), Sc(1.0)]), SENTINEL);
    }
    assert_eq!(
        val("hfdconex", &[x2.clone(), c.clone(), Sc(1.0)]),
        -11111111111.0
    );
    let x = arr(&[0.1, 0.2, 0.3]);
    assert_eq!(
        val(
            "hfellipsoid",
            &[x.clone(), c.clone(), Sc(1.0), Sc(5e-7), Sc(1.0)]
        ),
        SENTINEL
    );
    assert_eq!(
        val("hfellcylz", &[x.clone(), c.clone(), Sc(-1e-7), Sc(1.0)]),
        SENTINEL
    );
    assert_eq!(
        val(
            "hfblock",
            &[x.clone(), c.clone(), Sc(1.0), Sc(-0.1), Sc(1.0)]
        ),
        SENTINEL
    );
    assert_eq!(
        val(
            "hfsuperell",
            &[
                x.clone(),
                c.clone(),
                Sc(1.0),
                Sc(1.0),
                Sc(1.0),
                Sc(0.0),
                Sc(1.0)
            ]
        ),
        SENTINEL
    );
    let e: &[Ta] = &[];
    let _ = e;
    assert_eq!(
        val(
            "hfblobby",
            &[
                x.clone(),
                arr(&[]),
                arr(&[]),
                arr(&[]),
                arr(&[]),
                arr(&[]),
                Sc(0.1)
            ]
        ),
        SENTINEL
    );
    // a cone with R = 0 is not a sentinel in C: inf/NaN arithmetic
    assert!(val("hfconex", &[x.clone(), c.clone(), Sc(0.0)]).is_infinite());
}

#[test]
fn blob_primitives_match_spec_formulas() {
    let x0 = [-0.5, 0.5, 0.0];
    let y0 = [0.0, 0.1, 0.6];
    let z0 = [0.0, 0.1, -0.2];
    let a = [2.0, 3.0, 2.5];
    let b = [1.0, 1.2, 0.8];
    let d = [1.5, 0.9, -2.0];
    for x in PTS.iter().chain(&[[0.1, 0.05, 0.0], [0.45, 0.3, 0.1]]) {
        let r2 = |i: usize| sq(x[0] - x0[i]) + sq(x[1] - y0[i]) + sq(x[2] - z0[i]);
        let blobby: f64 = (0..3).map(|i| b[i] * (-a[i] * r2(i)).exp()).sum::<f64>() - 0.4;
        let centres = [arr(&x0), arr(&y0), arr(&z0)];
        let mut ta = vec![arr(x)];
        ta.extend(centres.iter().cloned());
        let mut tb = ta.clone();
        tb.extend([arr(&a), arr(&b), Sc(0.4)]);
        assert_close(val("hfblobby", &tb), blobby);
        let mut mb = 0.0;
        for i in 0..3 {
            let r = r2(i).sqrt();
            if d[i] > 0.0 {
                if r <= d[i] / 3.0 {
                    mb += b[i] * (1.0 - 3.0 * sq(r / d[i]));
                } else if r < d[i] {
                    mb += 1.5 * b[i] * sq(1.0 - r / d[i]);
                }
            }
        }
        let mut tm = ta.clone();
        tm.extend([arr(&b), arr(&d), Sc(0.3)]);
        assert_close(val("hfmetaball", &tm), mb - 0.3);
        let ds = [1.2, 0.7, 1.5];
        let mut soft = 0.0;
        for (i, &di) in ds.iter().enumerate() {
            let r = r2(i).sqrt();
            if r <= di {
                soft += 1.0 - 22.0 * r.powi(2) / (9.0 * di.powi(2))
                    + 17.0 * r.powi(4) / (9.0 * di.powi(4))
                    - 4.0 * r.powi(6) / (9.0 * di.powi(6));
            }
        }
        let mut ts = ta.clone();
        ts.extend([arr(&ds), Sc(0.2)]);
        assert!(close(val("hfsoft", &ts), soft - 0.2, 1e-12, 1e-14));
        // conv point
        let pv = [-0.5, 0.0, 0.0, 0.5, 0.2, 0.1];
        let s = [1.5, 2.0];
        let mut f = 0.0;
        for n in 0..2 {
            let r2 = sq(x[0] - pv[3 * n]) + sq(x[1] - pv[3 * n + 1]) + sq(x[2] - pv[3 * n + 2]);
            f += 1.0 / sq(1.0 + s[n] * s[n] * r2);
        }
        assert_close(
            val("hfconvpoint", &[arr(x), arr(&pv), arr(&s), Sc(0.3)]),
            f - 0.3,
        );
    }
}

#[test]
fn transformations_match_spec_formulas() {
    for x in PTS {
        let t = transform(x, "hfscale3d", &[Sc(2.0), Sc(0.5), Sc(4.0)]);
        assert_eq!(t, vec![x[0] / 2.0, x[1] / 0.5, x[2] / 4.0]);
        let t = transform(x, "hfshift3d", &[Sc(2.0), Sc(0.5), Sc(4.0)]);
        assert_eq!(t, vec![x[0] - 2.0, x[1] - 0.5, x[2] - 4.0]);
        let th: f64 = 0.7;
        let (ct, st) = (th.cos(), th.sin());
        let t = transform(x, "hfrotate3dz", &[Sc(th)]);
        assert_eq!(t, vec![x[0] * ct + x[1] * st, -x[0] * st + x[1] * ct, x[2]]);
        let t = transform(x, "hfrotate3dx", &[Sc(th)]);
        assert_eq!(t, vec![x[0], x[1] * ct + x[2] * st, -x[1] * st + x[2] * ct]);
        let t = transform(x, "hfrotate3dy", &[Sc(th)]);
        assert_eq!(t, vec![-x[2] * st + x[0] * ct, x[1], x[2] * ct + x[0] * st]);
        // twist Z
        let tt = (x[2] - -1.0) / (2.0 - -1.0);
        let th = (1.0 - tt) * 0.2 + tt * 1.1;
        let (ct, st) = (th.cos(), th.sin());
        let t = transform(x, "hftwistz", &[Sc(-1.0), Sc(2.0), Sc(0.2), Sc(1.1)]);
        assert_eq!(t, vec![x[0] * ct + x[1] * st, -x[0] * st + x[1] * ct, x[2]]);
        // taper Y (scales z and x)
        let scale = if x[1] < -0.5 {
            0.0
        } else if x[1] > 0.5 {
            2.0
        } else {
            let t = (x[1] + 0.5) / 1.0;
            (1.0 - t) * 0.0 + t * 2.0
        };
        let scale = if scale.abs() < 1e-6 { 1.0 } else { scale };
        let t = transform(x, "hftapery", &[Sc(-0.5), Sc(0.5), Sc(0.0), Sc(2.0)]);
        assert_eq!(t, vec![x[0] / scale, x[1], x[2] / scale]);
        let t = transform(
            x,
            "hfstretch3d",
            &[arr(&[0.1, 0.2, 0.3]), Sc(2.0), Sc(3.0), Sc(0.5)],
        );
        assert_eq!(
            t,
            vec![
                0.1 + (x[0] - 0.1) / 2.0,
                0.2 + (x[1] - 0.2) / 3.0,
                0.3 + (x[2] - 0.3) / 0.5
            ]
        );
        // space maps with two source points
        let src = [0.0, 0.0, 1.0, 1.0, 0.0, 0.0];
        let tgt = [0.0, 0.5, 1.5, 1.2, -0.3, 0.0];
        let bb = [0.5, 0.6, 0.7, 1.0, 1.1, 0.9];
        for cubic in [false, true] {
            let mut p = x;
            for i in [0, 3] {
                let dt = [
                    tgt[i] - src[i],
                    tgt[i + 1] - src[i + 1],
                    tgt[i + 2] - src[i + 2],
                ];
                let u: f64 = (0..3)
                    .map(|k| sq((p[k] - tgt[i + k]) / (bb[i + k] * (1.0 + dt[k].abs()))))
                    .sum();
                let w = if cubic {
                    let r = u.sqrt();
                    if r <= 1.0 {
                        (1.0 - r).powi(3) / (1.0 + r)
                    } else {
                        0.0
                    }
                } else {
                    (-u).exp()
                };
                for k in 0..3 {
                    p[k] -= w * dt[k];
                }
            }
            let name = if cubic {
                "hfspacemapcubic"
            } else {
                "hfspacemapexp"
            };
            let t = transform(x, name, &[arr(&src), arr(&tgt), arr(&bb)]);
            for k in 0..3 {
                assert_close(t[k], p[k]);
            }
        }
    }
}

#[test]
fn attributes() {
    let (r, arrays) = run(
        "hfa_setcolor",
        &[
            Sc(0.5),
            arr(&[9.0, 9.0, 9.0, 9.0]),
            Sc(0.1),
            Sc(0.2),
            Sc(0.3),
        ],
    );
    assert_eq!(r, 1.0);
    assert_eq!(arrays[1], vec![0.1, 0.2, 0.3, 9.0]);
    let (_, arrays) = run(
        "hfa_setcolor",
        &[Sc(0.0), arr(&[9.0; 3]), Sc(0.1), Sc(0.2), Sc(0.3)],
    );
    assert_eq!(arrays[1], vec![0.1, 0.2, 0.3], "f >= 0 sets");
    let (_, arrays) = run(
        "hfa_setcolor",
        &[Sc(-1e-9), arr(&[9.0; 3]), Sc(0.1), Sc(0.2), Sc(0.3)],
    );
    assert_eq!(arrays[1], vec![9.0; 3]);
    let (r, arrays) = run(
        "hfa_setattributes",
        &[Sc(1.0), arr(&[0.0; 3]), arr(&[1.0, 2.0])],
    );
    assert_eq!(r, 1.0);
    assert_eq!(arrays[1], vec![1.0, 2.0, 0.0]);
    let (_, arrays) = run(
        "hfa_setattributes",
        &[Sc(-1.0), arr(&[0.0; 3]), arr(&[1.0, 2.0])],
    );
    assert_eq!(arrays[1], vec![0.0; 3]);
    let e = run_err(
        "hfa_setcolor",
        &[Sc(1.0), arr(&[0.0; 2]), Sc(0.1), Sc(0.2), Sc(0.3)],
    );
    assert_eq!(e.arg, 1);
}

#[test]
fn argument_errors() {
    let x = arr(&[0.1, 0.2, 0.3]);
    let e = run_err("hfsphere", &[x.clone(), arr(&[0.0, 0.0]), Sc(1.0)]);
    assert_eq!(e.arg, 1);
    assert!(e.message.contains("center"), "{}", e.message);
    let e = run_err(
        "hfblobby",
        &[
            x.clone(),
            arr(&[0.0; 3]),
            arr(&[0.0; 3]),
            arr(&[0.0; 2]),
            arr(&[1.0; 3]),
            arr(&[1.0; 3]),
            Sc(0.1),
        ],
    );
    assert_eq!(e.arg, 3);
    let e = run_err(
        "hfconvline",
        &[
            x.clone(),
            arr(&[1.0, 2.0, 3.0]),
            arr(&[1.0, 2.0, 3.0]),
            arr(&[1.0]),
            Sc(0.1),
        ],
    );
    assert!(e.message.contains("same coordinates"), "{}", e.message);
    let e = run_err(
        "hfconvline",
        &[
            x.clone(),
            arr(&[1.0; 3]),
            arr(&[1.0; 2]),
            arr(&[1.0]),
            Sc(0.1),
        ],
    );
    assert_eq!(e.arg, 2);
    let e = run_err("hfscale3d", &[arr(&[1.0, 2.0]), Sc(1.0), Sc(1.0), Sc(1.0)]);
    assert_eq!(e.arg, 0);
    let e = run_err(
        "hfspacemapexp",
        &[x.clone(), arr(&[1.0; 4]), arr(&[1.0; 4]), arr(&[1.0; 4])],
    );
    assert_eq!(e.arg, 1);
    let e = run_err(
        "hfspacemapexp",
        &[x.clone(), arr(&[1.0; 3]), arr(&[1.0; 3]), arr(&[1.0; 2])],
    );
    assert_eq!(e.arg, 3);
    let e = run_err(
        "hfconvmesh",
        &[
            x.clone(),
            arr(&[0.0; 9]),
            arr(&[1.0, 2.0, 4.0]),
            arr(&[1.0]),
            Sc(0.1),
        ],
    );
    assert_eq!(e.arg, 2);
    // symbolic mesh indices
    let mut g = Graph::new();
    let mut args = to_args(
        &mut g,
        &[
            x.clone(),
            arr(&[0.0; 9]),
            arr(&[1.0, 2.0, 3.0]),
            arr(&[1.0]),
            Sc(0.1),
        ],
    );
    if let LibArg::Array(v) = &mut args[2] {
        v[1] = g.param(0);
    }
    let e = (lookup("hfconvmesh").unwrap().build)(&mut g, &mut args).unwrap_err();
    assert!(e.message.contains("constant"));
}

// ---------------------------------------------------------------------------
// Convolution surfaces against quadrature of the Cauchy kernel

fn kernel(s: f64, r2: f64) -> f64 {
    1.0 / sq(1.0 + s * s * r2)
}

/// Composite Simpson rule of `f` over `[a, b]` with `n` (even) intervals.
fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let mut s = f(a) + f(b);
    for i in 1..n {
        s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    sq(a[0] - b[0]) + sq(a[1] - b[1]) + sq(a[2] - b[2])
}

fn segment_integral(x: [f64; 3], b: [f64; 3], e: [f64; 3], s: f64) -> f64 {
    let l = dist2(b, e).sqrt();
    simpson(
        |t| {
            let u = t / l;
            let p = [
                b[0] + u * (e[0] - b[0]),
                b[1] + u * (e[1] - b[1]),
                b[2] + u * (e[2] - b[2]),
            ];
            kernel(s, dist2(x, p))
        },
        0.0,
        l,
        4000,
    )
}

const QPTS: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [0.3, 0.4, 0.2],
    [-1.1, 0.5, -0.3],
    [0.7, -0.6, 0.9],
    [2.0, 0.1, 0.1],
];

#[test]
fn conv_line_and_curve_match_quadrature() {
    let b = [-1.0, 0.2, 0.0, 0.3, -0.5, 0.4];
    let e = [1.0, -0.1, 0.3, 0.0, 1.0, -0.2];
    let s = [2.0, 1.3];
    for x in QPTS {
        let want: f64 = (0..2)
            .map(|n| segment_integral(x, triple_f(&b, 3 * n), triple_f(&e, 3 * n), s[n]))
            .sum();
        let got = val(
            "hfconvline",
            &[arr(&x), arr(&b), arr(&e), arr(&s), Sc(0.25)],
        );
        assert!(
            close(got, want - 0.25, 1e-6, 1e-9),
            "line at {x:?}: {got} vs {}",
            want - 0.25
        );
        let v = [
            -1.0, 0.0, 0.0, -0.3, 0.5, 0.0, 0.3, -0.5, 0.1, 1.0, 0.0, 0.0,
        ];
        let sc = [2.0, 1.5, 1.0];
        let want: f64 = (0..3)
            .map(|n| segment_integral(x, triple_f(&v, 3 * n), triple_f(&v, 3 * n + 3), sc[n]))
            .sum();
        let got = val("hfconvcurve", &[arr(&x), arr(&v), arr(&sc), Sc(0.0)]);
        assert!(
            close(got, want, 1e-6, 1e-9),
            "curve at {x:?}: {got} vs {want}"
        );
    }
}

fn triple_f(v: &[f64], i: usize) -> [f64; 3] {
    [v[i], v[i + 1], v[i + 2]]
}

/// Rodrigues rotation of `v` about the unit axis `k` by `a` radians.
fn rodrigues(v: [f64; 3], k: [f64; 3], a: f64) -> [f64; 3] {
    let (c, s) = (a.cos(), a.sin());
    let kv = [
        k[1] * v[2] - k[2] * v[1],
        k[2] * v[0] - k[0] * v[2],
        k[0] * v[1] - k[1] * v[0],
    ];
    let kd = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    [
        v[0] * c + kv[0] * s + k[0] * kd * (1.0 - c),
        v[1] * c + kv[1] * s + k[1] * kd * (1.0 - c),
        v[2] * c + kv[2] * s + k[2] * kd * (1.0 - c),
    ]
}

#[test]
fn conv_arc_matches_quadrature() {
    let rd = 3.141592 / 180.0;
    // (centre, radius, theta [deg], axis, angle [deg], S)
    let arcs: [([f64; 3], f64, f64, [f64; 3], f64, f64); 4] = [
        ([0.0, 0.0, 0.0], 1.0, 90.0, [0.0, 0.0, 1.0], -1e-6, 2.0),
        ([0.2, -0.1, 0.3], 0.8, 150.0, [1.0, 0.0, 0.0], 45.0, 1.5),
        ([0.0, 0.0, 0.0], 1.2, 270.0, [0.0, 1.0, 1.0], 30.0, 2.0),
        ([0.1, 0.1, 0.0], 0.7, 400.0, [0.0, 0.0, 1.0], 10.0, 1.8),
    ];
    let xs = [
        [0.05, -0.3, 0.2],
        [0.5, 0.6, 0.1],
        [-0.7, 0.3, -0.2],
        [1.1, -0.2, 0.4],
    ];
    for (ci, &(ctr, r, theta, axis, angle, s)) in arcs.iter().enumerate() {
        // the arc's points: c + R(axis', angle') (r cos t, r sin t, 0), t in [0, theta]
        let ang = (angle + 1e-6) * rd;
        let ax = [axis[0] + 1e-6, axis[1] + 1e-6, axis[2] + 1e-6];
        let l = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        let k = [ax[0] / l, ax[1] / l, ax[2] / l];
        let th = theta.min(360.0) * rd;
        for x in xs {
            let want = simpson(
                |t| {
                    let p = rodrigues([r * t.cos(), r * t.sin(), 0.0], k, ang);
                    let p = [p[0] + ctr[0], p[1] + ctr[1], p[2] + ctr[2]];
                    // the C closed form integrates over the angle, not the arc length
                    kernel(s, dist2(x, p))
                },
                0.0,
                th,
                6000,
            );
            let ta = [
                arr(&x),
                arr(&ctr),
                arr(&[r]),
                arr(&[theta]),
                arr(&axis),
                arr(&[angle]),
                arr(&[s]),
                Sc(0.0),
            ];
            let (got, arrays) = run("hfconvarc", &ta);
            assert!(
                close(got, want, 1e-6, 1e-9),
                "arc {ci} at {x:?}: {got} vs {want}"
            );
            // the arrays are updated in place
            assert_eq!(arrays[5], vec![angle + 1e-6]);
            assert_eq!(arrays[3], vec![theta.min(360.0).min(180.0)]);
        }
    }
}

/// Integral of the kernel over the triangle `a b c` (Duffy map, Simpson).
fn triangle_integral(x: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3], s: f64) -> f64 {
    let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let e2 = [c[0] - b[0], c[1] - b[1], c[2] - b[2]];
    let cr = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let area2 = (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]).sqrt();
    simpson(
        |u| {
            u * area2
                * simpson(
                    |v| {
                        let p = [
                            a[0] + u * e1[0] + u * v * e2[0],
                            a[1] + u * e1[1] + u * v * e2[1],
                            a[2] + u * e1[2] + u * v * e2[2],
                        ];
                        kernel(s, dist2(x, p))
                    },
                    0.0,
                    1.0,
                    200,
                )
        },
        0.0,
        1.0,
        200,
    )
}

#[test]
fn conv_triangle_and_mesh_match_quadrature() {
    let tris = [
        [-0.5, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.8, 0.0],
        [0.3, -0.2, 0.1, -0.4, 0.6, 0.5, 0.2, 0.9, -0.3],
    ];
    let s: [f64; 2] = [1.5, 2.0];
    let all: Vec<f64> = tris.iter().flatten().copied().collect();
    for x in QPTS {
        let mut want = 0.0;
        for (t, &sn) in tris.iter().zip(&s) {
            // The C closed form is S³ times the kernel's area integral.
            want += sn.powi(3)
                * triangle_integral(x, triple_f(t, 0), triple_f(t, 3), triple_f(t, 6), sn);
        }
        let got = val("hfconvtriangle", &[arr(&x), arr(&all), arr(&s), Sc(0.0)]);
        assert!(
            close(got, want, 1e-6, 1e-9),
            "triangle at {x:?}: {got} vs {want}"
        );
        // the same two triangles as a mesh sharing vertex lists
        let verts = all.clone();
        let tri = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let got_m = val(
            "hfconvmesh",
            &[arr(&x), arr(&verts), arr(&tri), arr(&s), Sc(0.0)],
        );
        assert_eq!(got_m, got);
        // vertex order does not matter (the C code reorders them)
        let rot: Vec<f64> = [&tris[0][3..], &tris[0][..3], &tris[1][6..], &tris[1][..6]].concat();
        let got_r = val("hfconvtriangle", &[arr(&x), arr(&rot), arr(&s), Sc(0.0)]);
        assert!(close(got_r, want, 1e-6, 1e-9));
    }
}

#[test]
fn conv_line_r_is_clamped_and_normalised() {
    // A single segment: f - T is 0 on the segment's surface at distance R
    // from its middle.
    let b = [-1.0, 0.0, 0.0];
    let e = [1.0, 0.0, 0.0];
    let r = 0.5;
    let on = val(
        "hfconvliner",
        &[arr(&[0.0, 0.0, 0.0]), arr(&b), arr(&e), Sc(r)],
    );
    assert!(on > 0.0);
    let far = val(
        "hfconvliner",
        &[arr(&[0.0, 3.0, 0.0]), arr(&b), arr(&e), Sc(r)],
    );
    assert!(far < 0.0);
    // the independent formula with S = 1/R
    let s = 1.0 / r;
    let l: f64 = 2.0;
    let pt = (1.0 + s * s * r * r).sqrt();
    let qt2 = 1.0 + s * s * (r * r + l * l);
    let t = l / (2.0 * pt * pt * qt2) + (s * l / pt).atan() / (2.0 * s * pt * pt * pt);
    let x = [0.3, 0.2, 0.1];
    let d = [x[0] + 1.0, x[1], x[2]];
    let xx = d[0];
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let p = (1.0 + s * s * (dd - xx * xx)).sqrt();
    let q2 = 1.0 + s * s * (dd + l * l - 2.0 * l * xx);
    let f = xx / (2.0 * p * p * (p * p + s * s * xx * xx))
        + (l - xx) / (2.0 * p * p * q2)
        + ((s * xx / p).atan() + (s * (l - xx) / p).atan()) / (2.0 * s * p * p * p);
    let got = val("hfconvliner", &[arr(&x), arr(&b), arr(&e), Sc(r)]);
    assert_close(got, f.min(1.0) - t);
}

// ---------------------------------------------------------------------------
// Symbolic builds agree with constant ones

/// Evaluates node `out` of `g` at the point `x` with parameters `a`.
fn eval(g: &Graph, out: NodeId, x: &[f64], a: &[f64]) -> f64 {
    let mut v = vec![0.0; g.len()];
    for (i, n) in g.nodes().iter().enumerate() {
        let r = match *n {
            Node::Const(_) => Ok(n.const_value().unwrap()),
            Node::X(k) => Ok(x[k as usize]),
            Node::Param(k) => Ok(a[k as usize]),
            Node::Error(e) => Err(e),
            Node::Unary(op, p) => ops::unary(op, v[p.index()]),
            Node::Binary(op, p, q) => ops::binary(op, v[p.index()], v[q.index()]),
            Node::PowI(p, k) => ops::pow_int(v[p.index()], k),
            Node::Select(c, t, e) => Ok(if ops::truthy(v[c.index()]) {
                v[t.index()]
            } else {
                v[e.index()]
            }),
            Node::Blend(op, p) => {
                let w = p.map(|q| v[q.index()]);
                Ok(ops::blend(op, w[0], w[1], w[2], w[3], w[4]))
            }
            Node::Check(_, q) => Ok(v[q.index()]),
        };
        v[i] = r.unwrap_or(f64::NAN);
    }
    v[out.index()]
}

/// Builds `name` with every scalar and array item symbolic (parameters),
/// evaluates it at the values of `ta`, and compares value and arrays with
/// the constant build bit for bit.
fn check_symbolic(name: &str, ta: &[Ta]) {
    let (want, want_arrays) = run(name, ta);
    let mut g = Graph::new();
    let mut params = Vec::new();
    let mut args = Vec::new();
    for t in ta {
        match t {
            Sc(v) => {
                args.push(LibArg::Scalar(g.param(params.len() as u32)));
                params.push(*v);
            }
            Arr(vs) => {
                let mut items = Vec::new();
                for &v in vs {
                    items.push(g.param(params.len() as u32));
                    params.push(v);
                }
                args.push(LibArg::Array(items));
            }
        }
    }
    let f = lookup(name).unwrap();
    let r = (f.build)(&mut g, &mut args).unwrap();
    let got = eval(&g, r, &[], &params);
    assert!(
        got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
        "{name}: symbolic {got:?} vs constant {want:?}"
    );
    for (a, w) in args.iter().zip(&want_arrays) {
        if let LibArg::Array(items) = a {
            let vals: Vec<f64> = items.iter().map(|&n| eval(&g, n, &[], &params)).collect();
            assert_eq!(&vals, w, "{name}: arrays");
        }
    }
}

#[test]
fn symbolic_builds_match_constant_builds() {
    let c = arr(&[0.1, -0.2, 0.3]);
    for x in PTS.iter().chain(&[[0.3, 0.1, 0.2], [0.12, -0.1, 0.31]]) {
        let xa = arr(x);
        check_symbolic(
            "hfellipsoid",
            &[xa.clone(), c.clone(), Sc(1.0), Sc(0.5), Sc(0.7)],
        );
        check_symbolic(
            "hfellipsoid",
            &[xa.clone(), c.clone(), Sc(1.0), Sc(0.0), Sc(0.7)],
        );
        check_symbolic(
            "hfblock",
            &[xa.clone(), c.clone(), Sc(1.0), Sc(0.5), Sc(0.7)],
        );
        check_symbolic(
            "hfblock",
            &[xa.clone(), c.clone(), Sc(1.0), Sc(-0.5), Sc(0.7)],
        );
        check_symbolic(
            "hfsuperell",
            &[
                xa.clone(),
                c.clone(),
                Sc(1.0),
                Sc(0.5),
                Sc(0.7),
                Sc(0.4),
                Sc(2.5),
            ],
        );
        let cs = [
            arr(&[-0.5, 0.5, 0.0]),
            arr(&[0.0, 0.1, 0.6]),
            arr(&[0.0, 0.1, -0.2]),
        ];
        let mut ta = vec![xa.clone()];
        ta.extend(cs.iter().cloned());
        let mut tm = ta.clone();
        tm.extend([arr(&[1.0, 1.5, 0.8]), arr(&[1.5, 0.3, -2.0]), Sc(0.3)]);
        check_symbolic("hfmetaball", &tm);
        let mut ts = ta.clone();
        ts.extend([arr(&[1.2, 0.7, 1.5]), Sc(0.2)]);
        check_symbolic("hfsoft", &ts);
        for name in ["hftaperx", "hftapery", "hftaperz"] {
            check_symbolic(name, &[xa.clone(), Sc(-0.5), Sc(0.5), Sc(0.0), Sc(2.0)]);
        }
        let sm = [
            arr(&[0.0, 0.0, 1.0]),
            arr(&[0.0, 0.3, 1.5]),
            arr(&[0.5, 0.5, 0.7]),
        ];
        let mut t = vec![xa.clone()];
        t.extend(sm.iter().cloned());
        check_symbolic("hfspacemapcubic", &t);
        check_symbolic("hfspacemapexp", &t);
        check_symbolic(
            "hfa_setcolor",
            &[Sc(x[0]), arr(&[0.0; 3]), Sc(0.1), Sc(0.2), Sc(0.3)],
        );
        for theta in [90.0, 200.0, 500.0] {
            check_symbolic(
                "hfconvarc",
                &[
                    xa.clone(),
                    arr(&[0.1, 0.0, 0.0]),
                    arr(&[0.9]),
                    arr(&[theta]),
                    arr(&[0.0, 1.0, 0.5]),
                    arr(&[20.0]),
                    arr(&[1.7]),
                    Sc(0.1),
                ],
            );
        }
        let tris = [
            0.3, -0.2, 0.1, -0.4, 0.6, 0.5, 0.2, 0.9, -0.3, -0.5, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0,
            0.8, 0.0,
        ];
        check_symbolic(
            "hfconvtriangle",
            &[xa.clone(), arr(&tris), arr(&[1.5, 2.0]), Sc(0.1)],
        );
        check_symbolic(
            "hfconvliner",
            &[
                xa.clone(),
                arr(&[-1.0, 0.0, 0.0]),
                arr(&[1.0, 0.0, 0.0]),
                Sc(0.4),
            ],
        );
    }
}

// ---------------------------------------------------------------------------
// Exhaustiveness

/// The function table of the reference (`int_global.c`, `functions_info`,
/// library part), with each entry's parameter kinds.
const REFERENCE_TABLE: &[(&str, &str)] = &[
    ("hfsphere", "AAR"),
    ("hfellipsoid", "AARRR"),
    ("hftorusz", "AARR"),
    ("hftorusx", "AARR"),
    ("hftorusy", "AARR"),
    ("hfellcylx", "AARR"),
    ("hfellcyly", "AARR"),
    ("hfellcylz", "AARR"),
    ("hfcylinderx", "AAR"),
    ("hfcylindery", "AAR"),
    ("hfcylinderz", "AAR"),
    ("hfblock", "AARRR"),
    ("hfblobby", "AAAAAAR"),
    ("hfmetaball", "AAAAAAR"),
    ("hfsoft", "AAAAAR"),
    ("hfscale3d", "ARRR"),
    ("hfshift3d", "ARRR"),
    ("hfrotate3dz", "AR"),
    ("hfrotate3dy", "AR"),
    ("hfrotate3dx", "AR"),
    ("hfblenduni", "RRRRR"),
    ("hfblendint", "RRRRR"),
    ("hftwistz", "ARRRR"),
    ("hftwisty", "ARRRR"),
    ("hftwistx", "ARRRR"),
    ("hfstretch3d", "AARRR"),
    ("hftaperz", "ARRRR"),
    ("hftapery", "ARRRR"),
    ("hftaperx", "ARRRR"),
    ("hfconvpoint", "AAAR"),
    ("hfconvline", "AAAAR"),
    ("hfconvarc", "AAAAAAAR"),
    ("hfconvtriangle", "AAAR"),
    ("hfbeziervolume", "ARRRAA"),
    ("hfconvliner", "AAAR"),
    ("hfconvcurve", "AAAR"),
    ("hfconvmesh", "AAAAR"),
    ("hfnoiseg", "ARRR"),
    ("hfsuperell", "AARRRRR"),
    ("hfconex", "AAR"),
    ("hfconey", "AAR"),
    ("hfconez", "AAR"),
    ("hfellconex", "AARR"),
    ("hfellconey", "AARR"),
    ("hfellconez", "AARR"),
    ("hfspacemapcubic", "AAAA"),
    ("hfspacemapexp", "AAAA"),
    ("hfr", "AR"),
    ("hfa_wave", "RRRR"),
    ("hfa_checkerboard", "AAAAAA"),
    ("hfa_union", "RRAAAR"),
    ("hfa_crackles", "AARAA"),
    ("hfa_circles", "AAAA"),
    ("hfa_noiseg", "ARR"),
    ("hfa_noisep", "A"),
    ("hfa_turbulence", "AR"),
    ("hfa_setcolor", "RARRR"),
    ("hfa_setattributes", "RAA"),
    ("hfa_lerp", "AAARRR"),
    ("hfa_cerp", "AAARRR"),
    ("hfa_clamp", "RRR"),
    ("hfa_floor", "R"),
    ("hfa_pulse", "RRR"),
    ("hfa_lookuptable", "RAAA"),
    ("hfa_smoothlookuptable", "RAAA"),
    ("hfa_step", "RR"),
    ("hfa_smoothstep", "RRR"),
    ("hfa_modulo", "RR"),
    ("hfa_spline", "AARRR"),
    ("hfa_rgbtohsv", "AA"),
    ("hfa_hsvtorgb", "AA"),
    ("hfdconex", "AAR"),
    ("hfdconey", "AAR"),
    ("hfdconez", "AAR"),
    ("hfdcylinder", "AAAR"),
    ("hfdellipsoid", "AARRR"),
    ("hfdtorusx", "AARR"),
    ("hfdtorusy", "AARR"),
    ("hfdtorusz", "AARR"),
    ("hfduni", "RRRR"),
    ("hfdint", "RRRR"),
    ("hfdsub", "RRRR"),
    ("hfdblenduni", "RRR"),
    ("hfdblendint", "RRR"),
    ("hfsawtooth", "RRRR"),
];

/// Table entries deliberately not implemented (see the module docs).
const NOT_IMPLEMENTED: &[&str] = &[
    "hfbeziervolume",
    "hfr",
    "hfdellipsoid",
    "hfduni",
    "hfdint",
    "hfdsub",
    "hfdblenduni",
    "hfdblendint",
    "hfsawtooth",
    "hfa_wave",
    "hfa_checkerboard",
    "hfa_union",
    "hfa_crackles",
    "hfa_circles",
    "hfa_noiseg",
    "hfa_noisep",
    "hfa_turbulence",
    "hfa_lerp",
    "hfa_cerp",
    "hfa_clamp",
    "hfa_floor",
    "hfa_pulse",
    "hfa_lookuptable",
    "hfa_smoothlookuptable",
    "hfa_step",
    "hfa_smoothstep",
    "hfa_modulo",
    "hfa_spline",
    "hfa_rgbtohsv",
    "hfa_hsvtorgb",
];

#[test]
fn table_is_covered() {
    for &(name, kinds) in REFERENCE_TABLE {
        let Some(f) = lookup(name) else {
            assert!(
                NOT_IMPLEMENTED.contains(&name),
                "{name} is neither implemented nor listed"
            );
            continue;
        };
        assert!(!NOT_IMPLEMENTED.contains(&name), "{name} listed as missing");
        assert_eq!(f.name, name);
        let want: Vec<ParamKind> = kinds
            .chars()
            .map(|k| {
                if k == 'A' {
                    ParamKind::Array
                } else {
                    ParamKind::Scalar
                }
            })
            .collect();
        assert_eq!(f.params, want.as_slice(), "{name} parameters");
    }
    for f in all() {
        assert!(
            REFERENCE_TABLE.iter().any(|&(n, _)| n == f.name),
            "{} is not in the table",
            f.name
        );
        assert_eq!(f.name, f.name.to_ascii_lowercase());
    }
    let mut names: Vec<_> = all().iter().map(|f| f.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), all().len(), "duplicate names");
    assert_eq!(all().len() + NOT_IMPLEMENTED.len(), REFERENCE_TABLE.len());
    assert!(lookup("hfSphere").is_some());
    assert!(lookup("hfMetaBall").is_some());
    assert!(lookup("hfA_SetColor").is_some());
    assert!(lookup("hfnothing").is_none());
}
