//! Compiled models: diagnostics placed in the source, parameter sliders,
//! the graph hash, the box rule, the summary, the compile cache.

use frep_artefact::{compile, BoxOrigin, CompileCache, CompileLimits};

const SPHERE: &str = "my_model(x[3], a[1]) { my_model = 1 - x[1]^2 - x[2]^2 - x[3]^2; }";

#[test]
fn errors_are_placed_with_a_caret() {
    let src = "my_model(x[3], a[1])\n{\n  my_model = sqrt(x[1] + );\n}";
    let d = compile(src, None, &CompileLimits::default()).unwrap_err();
    assert_eq!(d.len(), 1);
    let d = &d[0];
    assert_eq!((d.line, d.column), (3, 26));
    assert_eq!(&src[d.start as usize..d.end as usize], ")");
    assert!(
        d.rendered.contains("3 |   my_model = sqrt(x[1] + );"),
        "{}",
        d.rendered
    );
    assert!(d.rendered.contains('^'));
    let big = "-".repeat(100);
    let limits = CompileLimits {
        max_source_bytes: 50,
        ..CompileLimits::default()
    };
    assert!(compile(&big, None, &limits).unwrap_err()[0]
        .message
        .contains("over the limit"));
}

#[test]
fn param_lines_name_the_sliders() {
    let src = "-- param: a[1] radius 0.8 0.1 2\n-- param: 3 twist 0.5\nmy_model(x[3], a[3]) { my_model = a[1] - x[1]^2 - x[2]^2 - x[3]^2 + 0*a[2] + 0*a[3]; }";
    let c = compile(src, None, &CompileLimits::default()).unwrap();
    let p = c.params();
    assert_eq!(p.len(), 3);
    assert_eq!(
        (p[0].name.as_str(), p[0].default, p[0].min, p[0].max),
        ("radius", 0.8, 0.1, 2.0)
    );
    assert_eq!(
        (p[1].name.as_str(), p[1].default, p[1].min, p[1].max),
        ("a[2]", 0.0, -1.0, 1.0)
    );
    assert_eq!(
        (p[2].name.as_str(), p[2].default, p[2].min, p[2].max),
        ("twist", 0.5, -0.5, 1.5)
    );
    assert_eq!(c.param_values(&[1.0]), vec![1.0, 0.0, 0.5]);
    // The extent is found at the default radius 0.8 (sqrt: about 0.89).
    assert_eq!(c.bounds_origin(), BoxOrigin::Extent);
    assert!(
        c.bounds()[3] > 0.89 && c.bounds()[3] < 1.1,
        "{:?}",
        c.bounds()
    );
}

#[test]
fn the_graph_hash_ignores_how_the_model_is_written() {
    let a = compile(SPHERE, None, &CompileLimits::default()).unwrap();
    let b = compile(
        "-- a comment\nmy_model(x[3], a[1])\n{\n  one = 3 - 2;\n  my_model = one - x[1]^2 - x[2]^2\n    - x[3]^2;\n}\n",
        None,
        &CompileLimits::default(),
    )
    .unwrap();
    let c = compile(
        "my_model(x[3], a[1]) { my_model = 2 - x[1]^2 - x[2]^2 - x[3]^2; }",
        None,
        &CompileLimits::default(),
    )
    .unwrap();
    assert_eq!(a.graph_hash(), b.graph_hash());
    assert_ne!(a.graph_hash(), c.graph_hash());
    assert_eq!(a.graph_hash().len(), 64);
}

#[test]
fn the_summary_describes_the_model() {
    let s = compile(SPHERE, None, &CompileLimits::default())
        .unwrap()
        .summary()
        .clone();
    assert_eq!(s.body, "my_model");
    assert_eq!(s.bounds_origin, "extent");
    assert!(s.bounds[0] < -1.0 && s.bounds[0] > -1.2, "{:?}", s.bounds);
    assert!(s.closed_form, "a sphere is a quadric");
    assert!(s.tape_len > 3 && s.nodes >= s.tape_len);
    assert!(s.shader_statements > 0);
    assert_eq!(s.params.len(), 1);
    assert_eq!(s.attributes, 0);
    let gyroid = "-- bounds: -1,-1,-1,1,1,1\nmy_model(x[3], a[1]) { my_model = sin(6*x[1])*cos(6*x[2]) + sin(6*x[2])*cos(6*x[3]) + sin(6*x[3])*cos(6*x[1]); }";
    let g = compile(gyroid, None, &CompileLimits::default()).unwrap();
    assert_eq!(g.bounds_origin(), BoxOrigin::Comment);
    assert!(!g.summary().closed_form);
    let half = compile(
        "my_model(x[3], a[1]) { my_model = x[3]; }",
        None,
        &CompileLimits::default(),
    )
    .unwrap();
    assert_eq!(half.bounds_origin(), BoxOrigin::Default);
    assert_eq!(half.summary().bounds_origin, "default");
}

#[test]
fn the_compile_cache_shares_models() {
    let cache = CompileCache::new(2);
    let l = CompileLimits::default();
    let a = cache.get_or_compile(SPHERE, None, &[], &l).unwrap();
    let b = cache.get_or_compile(SPHERE, None, &[], &l).unwrap();
    assert!(std::sync::Arc::ptr_eq(&a, &b));
    let other = SPHERE.replace("1 -", "2 -");
    cache.get_or_compile(&other, None, &[], &l).unwrap();
    cache
        .get_or_compile("m(x[3], a[1]) { m = 1; }", None, &[], &l)
        .unwrap();
    assert_eq!(cache.len(), 2);
    assert!(cache.get_or_compile("m(", None, &[], &l).is_err());
    assert_eq!(cache.len(), 2);
}

#[test]
fn closed_form_is_told_apart() {
    let closed = |name: &str| {
        let path = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
        let src = std::fs::read_to_string(path).unwrap();
        compile(&src, None, &CompileLimits::default())
            .unwrap()
            .summary()
            .closed_form
    };
    // Set expressions over at most 8 quadrics.
    assert!(closed("semi_sphere.hf"));
    assert!(closed("closed_cylinder.hf"));
    // Trigonometry; a hundred spheres (beyond 8 leaves).
    assert!(!closed("m3_gyroid.hf"));
    assert!(!closed("m2_spheres100.hf"));
}
