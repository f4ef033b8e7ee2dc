//! `GET /`: the server's own HTML page when no built studio is there — the
//! models, each with a server image and download links.
//!
//! The models come newest first, at most `limits.page_models`.
//! - Each one's latest version is compiled (cached). One image and five
//!   exports are registered with the artefact service.
//! - The page links their immutable URLs. So the images are computed when
//!   the browser asks for them (in parallel, bounded by the worker pool),
//!   and cached after.
//! - A model that does not compile shows its first diagnostic instead.
//! - Every text is HTML escaped: names and messages come from users.

use std::fmt::Write;

use axum::extract::State;
use axum::response::Html;
use frep_wire::{ArtefactSpec, CameraView, ExportFormat, ImageEncoding, ModelSummary};

use crate::compile::compile_source;
use crate::error::AppResult;
use crate::examples::description;
use crate::state::AppState;

/// Side of the page's images, pixels.
const IMAGE_SIDE: u32 = 256;
/// Octree depth of the page's downloads (a few hundred kB per file).
const EXPORT_DEPTH: u8 = 7;
/// The downloads offered, with their labels.
const EXPORTS: [(ExportFormat, &str); 5] = [
    (ExportFormat::Stl, "STL"),
    (ExportFormat::Obj, "OBJ"),
    (ExportFormat::Ply, "PLY"),
    (ExportFormat::Glb, "GLB"),
    (ExportFormat::ThreeMf, "3MF"),
];

/// The page.
pub async fn index(State(state): State<AppState>) -> AppResult<Html<String>> {
    let mut models = crate::models::list_models(&state).await?;
    models.sort_by(|a, b| b.updated.cmp(&a.updated).then(a.name.cmp(&b.name)));
    models.truncate(state.config.limits.page_models);
    let mut cards = String::new();
    for m in &models {
        cards.push_str(&card(&state, m).await);
    }
    Ok(Html(format!(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
<title>frep: models</title><style>{STYLE}</style></head><body>\
<header><h1>frep</h1><p>{n} models. The studio is not built here \
(<code>scripts/studio.sh</code> builds it); this page lists the models with a server image \
and downloads. API: <a href=\"/api/openapi.json\">/api/openapi.json</a>.</p></header>\
<main>{cards}</main></body></html>\n",
        n = models.len()
    )))
}

/// One model's card.
async fn card(state: &AppState, m: &ModelSummary) -> String {
    let mut html = format!(
        "<article><h2>{}</h2><p class=\"meta\">{} · version {}</p>",
        esc(&m.name),
        esc(&m.owner),
        m.latest
    );
    let version = match crate::versions::load_version(state, m.id.clone(), None).await {
        Ok(v) => v,
        Err(e) => {
            let _ = write!(
                html,
                "<p class=\"error\">{}</p></article>",
                esc(&e.body().message)
            );
            return html;
        }
    };
    if let Some(d) = description(&version.source) {
        let _ = write!(html, "<p>{}</p>", esc(d));
    }
    let compiled = match compile_source(state, version.source.clone(), None, Vec::new()).await {
        Ok(Ok(c)) => c,
        Ok(Err(diags)) => {
            let first = diags.first().map(|d| d.rendered.as_str()).unwrap_or("");
            let _ = write!(html, "<pre class=\"error\">{}</pre></article>", esc(first));
            return html;
        }
        Err(e) => {
            let _ = write!(
                html,
                "<p class=\"error\">{}</p></article>",
                esc(&e.body().message)
            );
            return html;
        }
    };
    let image = ArtefactSpec::Image {
        camera: CameraView::default(),
        width: IMAGE_SIDE,
        height: IMAGE_SIDE,
        format: ImageEncoding::Jpeg,
        quality: 80,
        section: None,
    };
    match state
        .artefacts
        .request(compiled.clone(), &version.params, image, None)
    {
        Ok(r) => {
            let _ = write!(
                html,
                "<img src=\"{}\" width=\"{IMAGE_SIDE}\" height=\"{IMAGE_SIDE}\" alt=\"{}\" loading=\"lazy\">",
                esc(&r.url),
                esc(&m.name)
            );
        }
        Err(e) => {
            let _ = write!(html, "<p class=\"error\">{}</p>", esc(&e.to_string()));
        }
    }
    html.push_str("<p class=\"downloads\">");
    for (format, label) in EXPORTS {
        let spec = ArtefactSpec::Export {
            format,
            depth: EXPORT_DEPTH,
        };
        if let Ok(r) = state
            .artefacts
            .request(compiled.clone(), &version.params, spec, None)
        {
            let _ = write!(
                html,
                "<a href=\"{}?name={}\" download>{label}</a> ",
                esc(&r.url),
                esc(&url_name(&m.name))
            );
        }
    }
    html.push_str("</p></article>");
    html
}

/// A model name as a `?name=` value: what the server keeps of it anyway
/// (letters, digits, `-`, `_`), the rest as `_`.
fn url_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// HTML text and attribute escaping.
pub fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "body{font:15px/1.4 system-ui,sans-serif;margin:0;background:#f4f4f2;color:#222}\
header{padding:1rem 2rem;background:#24323f;color:#eee}header a{color:#9cf}\
main{display:grid;grid-template-columns:repeat(auto-fill,minmax(280px,1fr));gap:1rem;padding:1rem 2rem}\
article{background:#fff;border-radius:6px;padding:.8rem;box-shadow:0 1px 3px #0002}\
article h2{margin:.2rem 0;font-size:1.1rem}.meta{color:#777;margin:0 0 .4rem}\
img{display:block;width:100%;height:auto;background:#ddd;border-radius:4px}\
.downloads a{margin-right:.5rem}.error{color:#a00;white-space:pre-wrap}";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup() {
        assert_eq!(
            esc("<a href=\"x\">&'"),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"
        );
        assert_eq!(url_name("sake pot!"), "sake_pot_");
    }
}
