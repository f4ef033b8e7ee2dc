//! 3MF: a zip package with the model as XML, unit millimetre, colours through the
//! materials extension (`m:colorgroup`, one colour per distinct 8-bit RGB value).

use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::{self, Cursor, Read, Write};

use zip::write::SimpleFileOptions;
use zip::CompressionMethod;

use super::{color_byte, invalid};
use crate::Mesh;

const MODEL_PATH: &str = "3D/3dmodel.model";

const CONTENT_TYPES: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">
 <Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>
 <Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>
</Types>
"#;

const RELS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">
 <Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>
</Relationships>
"#;

fn model_xml(mesh: &Mesh) -> String {
    let mut x = String::with_capacity(64 * mesh.positions.len() + 48 * mesh.triangles.len());
    x.push_str(concat!(
        r#"<?xml version="1.0" encoding="UTF-8"?>"#,
        "\n",
        r#"<model unit="millimeter" xml:lang="en-US" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02" xmlns:m="http://schemas.microsoft.com/3dmanufacturing/material/2015/02">"#,
        "\n <resources>\n"
    ));
    // Palette of distinct 8-bit colours; `slot[v]` is vertex v's entry.
    let mut palette: HashMap<[u8; 3], usize> = HashMap::new();
    let mut slot = Vec::with_capacity(mesh.colors.len());
    if !mesh.colors.is_empty() {
        x.push_str("  <m:colorgroup id=\"1\">\n");
        for c in &mesh.colors {
            let rgb = c.map(color_byte);
            let next = palette.len();
            let k = *palette.entry(rgb).or_insert_with(|| {
                let _ = writeln!(
                    x,
                    "   <m:color color=\"#{:02X}{:02X}{:02X}\"/>",
                    rgb[0], rgb[1], rgb[2]
                );
                next
            });
            slot.push(k);
        }
        x.push_str("  </m:colorgroup>\n");
    }
    x.push_str("  <object id=\"2\" type=\"model\"");
    if !slot.is_empty() {
        let _ = write!(
            x,
            " pid=\"1\" pindex=\"{}\"",
            slot.first().copied().unwrap_or(0)
        );
    }
    x.push_str(">\n   <mesh>\n    <vertices>\n");
    for [px, py, pz] in &mesh.positions {
        let _ = writeln!(x, "     <vertex x=\"{px}\" y=\"{py}\" z=\"{pz}\"/>");
    }
    x.push_str("    </vertices>\n    <triangles>\n");
    for &[a, b, c] in &mesh.triangles {
        let _ = write!(x, "     <triangle v1=\"{a}\" v2=\"{b}\" v3=\"{c}\"");
        if !slot.is_empty() {
            let [p1, p2, p3] = [a, b, c].map(|v| slot[v as usize]);
            let _ = write!(x, " pid=\"1\" p1=\"{p1}\" p2=\"{p2}\" p3=\"{p3}\"");
        }
        x.push_str("/>\n");
    }
    x.push_str("    </triangles>\n   </mesh>\n  </object>\n </resources>\n <build>\n  <item objectid=\"2\"/>\n </build>\n</model>\n");
    x
}

pub(super) fn write(mesh: &Mesh, w: &mut impl Write) -> io::Result<()> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
    for (name, text) in [
        ("[Content_Types].xml", CONTENT_TYPES.to_string()),
        ("_rels/.rels", RELS.to_string()),
        (MODEL_PATH, model_xml(mesh)),
    ] {
        zip.start_file(name, options).map_err(io::Error::other)?;
        zip.write_all(text.as_bytes())?;
    }
    let bytes = zip.finish().map_err(io::Error::other)?.into_inner();
    w.write_all(&bytes)?;
    w.flush()
}

/// The XML tags of a document as `(name, attributes)`, with any namespace prefix kept;
/// enough for the flat attribute-only elements of a 3MF mesh.
fn tags(xml: &str) -> impl Iterator<Item = (&str, Vec<(&str, &str)>)> {
    xml.split('<').skip(1).filter_map(|chunk| {
        let body = chunk.split('>').next()?;
        if body.starts_with(['/', '?', '!']) {
            return None;
        }
        let body = body.trim_end_matches('/');
        let name_end = body.find(|c: char| c.is_whitespace()).unwrap_or(body.len());
        let mut attrs = Vec::new();
        let mut rest = &body[name_end..];
        while let Some(eq) = rest.find('=') {
            let key = rest[..eq].trim();
            let after = rest[eq + 1..].trim_start();
            let quote = after.chars().next()?;
            let value_end = after[1..].find(quote)?;
            attrs.push((key, &after[1..1 + value_end]));
            rest = &after[value_end + 2..];
        }
        Some((&body[..name_end], attrs))
    })
}

fn attr<T: std::str::FromStr>(attrs: &[(&str, &str)], key: &str) -> io::Result<Option<T>> {
    match attrs.iter().find(|(k, _)| *k == key) {
        None => Ok(None),
        Some((_, v)) => v
            .parse()
            .map(Some)
            .map_err(|_| invalid(format!("3MF: bad {key}={v:?}"))),
    }
}

fn hex_color(s: &str) -> io::Result<[f32; 3]> {
    let hex = s
        .strip_prefix('#')
        .filter(|h| h.len() == 6 || h.len() == 8)
        .ok_or_else(|| invalid("3MF: bad colour"))?;
    let byte = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_err(invalid);
    Ok([
        byte(0)? as f32 / 255.0,
        byte(2)? as f32 / 255.0,
        byte(4)? as f32 / 255.0,
    ])
}

/// Reads the vertices and triangles of every mesh object in the model part (objects are
/// concatenated; build transforms are ignored) with the colours of the first colour group.
pub(super) fn read(bytes: &[u8]) -> io::Result<Mesh> {
    let mut archive = zip::ZipArchive::new(Cursor::new(bytes)).map_err(invalid)?;
    let mut xml = String::new();
    archive
        .by_name(MODEL_PATH)
        .map_err(invalid)?
        .read_to_string(&mut xml)?;
    let mut mesh = Mesh::default();
    let mut palette = Vec::new();
    let mut palette_id = None;
    let mut groups = 0;
    let mut corner_colors: Vec<(u32, usize)> = Vec::new();
    let mut base = 0u32;
    for (name, attrs) in tags(&xml) {
        let local = name.rsplit(':').next().unwrap_or(name);
        match local {
            "colorgroup" => {
                groups += 1;
                if groups == 1 {
                    palette_id = attr::<u32>(&attrs, "id")?;
                }
            }
            "color" if groups == 1 => {
                if let Some(c) = attrs.iter().find(|(k, _)| *k == "color") {
                    palette.push(hex_color(c.1)?);
                }
            }
            "mesh" => base = mesh.positions.len() as u32,
            "vertex" => {
                let get = |k| {
                    attr::<f32>(&attrs, k)?.ok_or_else(|| invalid("3MF: vertex coordinate missing"))
                };
                mesh.positions.push([get("x")?, get("y")?, get("z")?]);
            }
            "triangle" => {
                let get = |k| {
                    attr::<u32>(&attrs, k)?.ok_or_else(|| invalid("3MF: triangle index missing"))
                };
                let t = [get("v1")? + base, get("v2")? + base, get("v3")? + base];
                mesh.triangles.push(t);
                if palette_id.is_some() && attr::<u32>(&attrs, "pid")? == palette_id {
                    let p1: Option<usize> = attr(&attrs, "p1")?;
                    let p = [p1, attr(&attrs, "p2")?.or(p1), attr(&attrs, "p3")?.or(p1)];
                    for (v, p) in t.iter().zip(p) {
                        if let Some(p) = p {
                            corner_colors.push((*v, p));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    if !corner_colors.is_empty() {
        mesh.colors = vec![[1.0; 3]; mesh.positions.len()];
        for (v, p) in corner_colors {
            let c = palette
                .get(p)
                .ok_or_else(|| invalid("3MF: colour index out of range"))?;
            *mesh
                .colors
                .get_mut(v as usize)
                .ok_or_else(|| invalid("3MF: vertex index out of range"))? = *c;
        }
    }
    Ok(mesh)
}
