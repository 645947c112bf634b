//! The operator panel: a page, its scripts and the vendored `roslib`, compiled into the binary.

use axum::http::header;
use axum::response::{Html, IntoResponse};
use axum::routing::get;
use axum::Router;

/// The page.
const PAGE: &str = include_str!("../panel/index.html");
/// Its script.
const SCRIPT: &str = include_str!("../panel/panel.js");
/// Its way in: the token and `/whoami`.
const ACCESS: &str = include_str!("../panel/access.js");
/// Its small helpers: UUIDs, names, distances and DOM writes.
const HELPERS: &str = include_str!("../panel/helpers.js");
/// `roslib`'s browser build, from the npm package pinned in `panel/package-lock.json`
/// (`tools/vendor-roslib` copies it).
const ROSLIB: &str = include_str!("../panel/vendor/roslib.min.js");

pub(crate) fn page() -> Html<&'static str> {
    Html(PAGE)
}

fn script(text: &'static str) -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
        text,
    )
}

pub(crate) fn routes<S: Clone + Send + Sync + 'static>() -> Router<S> {
    Router::new()
        .route("/panel.js", get(|| async { script(SCRIPT) }))
        .route("/access.js", get(|| async { script(ACCESS) }))
        .route("/helpers.js", get(|| async { script(HELPERS) }))
        .route("/roslib.min.js", get(|| async { script(ROSLIB) }))
}
