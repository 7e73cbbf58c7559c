//! The page and what it loads, built into the binary: `protolink web` needs no network and
//! no files beside it.

/// The page: the instruments' layout.
pub const INDEX_HTML: &str = include_str!("assets/index.html");
/// The drawing code: the instruments on canvases, fed by server-sent events.
pub const APP_JS: &str = include_str!("assets/app.js");
/// The colours and layout.
pub const STYLE_CSS: &str = include_str!("assets/style.css");

/// The content type and bytes of the asset at `path`, or `None`.
///
/// ```
/// let (kind, body) = protolink::commands::web::assets::find("/").unwrap();
/// assert!(kind.starts_with("text/html") && !body.is_empty());
/// assert!(protolink::commands::web::assets::find("/../etc/passwd").is_none());
/// ```
pub fn find(path: &str) -> Option<(&'static str, &'static [u8])> {
    match path {
        "/" | "/index.html" => Some(("text/html; charset=utf-8", INDEX_HTML.as_bytes())),
        "/app.js" => Some(("text/javascript; charset=utf-8", APP_JS.as_bytes())),
        "/style.css" => Some(("text/css; charset=utf-8", STYLE_CSS.as_bytes())),
        _ => None,
    }
}
