//! Exhaustiveness: the reference function table is covered.

use super::*;

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
