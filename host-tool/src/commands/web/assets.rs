//! The page and what it loads, built into the binary: `protolink web` needs no network and
//! no files beside it.

/// The page: the instruments' layout.
pub(crate) const INDEX_HTML: &str = include_str!("assets/index.html");
/// The drawing code: the instruments on canvases, fed by server-sent events.
pub(crate) const APP_JS: &str = include_str!("assets/app.js");
/// The colours and layout.
pub(crate) const STYLE_CSS: &str = include_str!("assets/style.css");

/// The content type and bytes of the asset at `path`, or `None`.
pub(crate) fn find(path: &str) -> Option<(&'static str, &'static [u8])> {
    match path {
        "/" | "/index.html" => Some(("text/html; charset=utf-8", INDEX_HTML.as_bytes())),
        "/app.js" => Some(("text/javascript; charset=utf-8", APP_JS.as_bytes())),
        "/style.css" => Some(("text/css; charset=utf-8", STYLE_CSS.as_bytes())),
        _ => None,
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn find_example() -> Result<(), Box<dyn std::error::Error>> {
        let (kind, body) = find("/").unwrap();
        assert!(kind.starts_with("text/html") && !body.is_empty());
        assert!(find("/../etc/passwd").is_none());
        Ok(())
    }
}
