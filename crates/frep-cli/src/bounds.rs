//! The model box: `--bounds` values and the `-- bounds:` comment line of
//! the examples.

/// Parses six comma-separated numbers `x0,y0,z0,x1,y1,z1` into the corners
/// `(min, max)` (each coordinate sorted).
pub fn parse_bounds(text: &str) -> Result<([f64; 3], [f64; 3]), String> {
    let v: Vec<f64> = text
        .split(',')
        .map(|s| {
            s.trim()
                .parse::<f64>()
                .map_err(|_| format!("`{}` is not a number", s.trim()))
        })
        .collect::<Result<_, _>>()?;
    if v.len() != 6 || v.iter().any(|x| !x.is_finite()) {
        return Err(format!(
            "expected six finite numbers x0,y0,z0,x1,y1,z1, got `{text}`"
        ));
    }
    let min = [v[0].min(v[3]), v[1].min(v[4]), v[2].min(v[5])];
    let max = [v[0].max(v[3]), v[1].max(v[4]), v[2].max(v[5])];
    if (0..3).any(|k| min[k] == max[k]) {
        return Err(format!("the box `{text}` is flat"));
    }
    Ok((min, max))
}

/// The box from the first `-- bounds: x0,y0,z0,x1,y1,z1` comment line of a
/// model's source, if any.
pub fn bounds_from_source(source: &str) -> Option<([f64; 3], [f64; 3])> {
    source
        .lines()
        .find_map(|l| l.trim().strip_prefix("-- bounds:"))
        .and_then(|rest| parse_bounds(rest).ok())
}

/// HyperFun's default box (`hfp`'s `-b 10`): `[-10, 10]³`.
pub const DEFAULT_BOUNDS: ([f64; 3], [f64; 3]) = ([-10.0; 3], [10.0; 3]);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_sorts() {
        assert_eq!(
            parse_bounds("1,-1, -2,-1,1,2"),
            Ok(([-1.0, -1.0, -2.0], [1.0, 1.0, 2.0]))
        );
        assert!(parse_bounds("1,2,3").is_err());
        assert!(parse_bounds("0,0,0,1,1,x").is_err());
        assert!(parse_bounds("0,0,0,1,1,0").is_err());
    }

    #[test]
    fn reads_comment_line() {
        let src = "-- description: x\n-- bounds: -0.5,-1,-1,0.5,1,1\nm(x[3], a[1]) { m = 1; }";
        assert_eq!(
            bounds_from_source(src),
            Some(([-0.5, -1.0, -1.0], [0.5, 1.0, 1.0]))
        );
        assert_eq!(bounds_from_source("m(x[3], a[1]) { m = 1; }"), None);
    }
}
