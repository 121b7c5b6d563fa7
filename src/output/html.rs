//! `report.html`: a Markdown report as one self-contained HTML file
//! (pulldown-cmark, every PNG embedded as base64), for `paper` and
//! `benchmarks`.

use anyhow::{anyhow, Result};
use base64::engine::general_purpose::STANDARD as BASE64;
use base64::Engine as _;
use std::path::Path;

/// The report as one HTML file, every PNG embedded.
pub fn report_html(markdown: &str, dir: &Path, page_title: &str) -> Result<String> {
    use pulldown_cmark::{html, Event, Options, Parser, Tag};
    let parser = Parser::new_ext(markdown, Options::ENABLE_TABLES);
    let mut failed = None;
    let events: Vec<Event> = parser
        .map(|e| match e {
            Event::Start(Tag::Image {
                link_type,
                dest_url,
                title,
                id,
            }) if !dest_url.starts_with("data:") => {
                let path = dir.join(dest_url.as_ref());
                match std::fs::read(&path) {
                    Ok(bytes) => Event::Start(Tag::Image {
                        link_type,
                        dest_url: format!("data:image/png;base64,{}", BASE64.encode(&bytes)).into(),
                        title,
                        id,
                    }),
                    Err(err) => {
                        failed.get_or_insert(anyhow!("cannot embed {}: {err}", path.display()));
                        Event::Start(Tag::Image {
                            link_type,
                            dest_url,
                            title,
                            id,
                        })
                    }
                }
            }
            e => e,
        })
        .collect();
    if let Some(e) = failed {
        return Err(e);
    }
    let mut body = String::new();
    html::push_html(&mut body, events.into_iter());
    Ok(format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>{page_title}</title>\n<style>\n\
         body {{ font-family: sans-serif; max-width: 1100px; margin: 2em auto; padding: 0 1em; line-height: 1.45; }}\n\
         table {{ border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }}\n\
         th, td {{ border: 1px solid #bbb; padding: 0.25em 0.5em; }}\n\
         th {{ background: #f0f0f0; }}\n img {{ max-width: 100%; border: 1px solid #ddd; }}\n\
         code {{ background: #f4f4f4; padding: 0 0.2em; }}\n</style>\n</head>\n<body>\n{body}</body>\n</html>\n"
    ))
}
