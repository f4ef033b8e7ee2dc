//! Golden values of the reference interpreter, primitive by primitive.

use super::*;

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

/// One golden file per primitive, one block each: long, but flat.
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
