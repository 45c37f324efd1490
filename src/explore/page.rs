//! The page's files, compiled into the binary: nothing is fetched at run time. uPlot 1.6.32
//! (MIT licence, `assets/uplot/LICENSE`) comes from the npm registry
//! (`npm pack uplot@1.6.32`: `dist/uPlot.iife.min.js`, `dist/uPlot.min.css`).

/// The page.
pub const HTML: &str = include_str!("assets/index.html");
/// Its script.
pub const APP_JS: &str = include_str!("assets/app.js");
/// Its style.
pub const APP_CSS: &str = include_str!("assets/app.css");
/// uPlot's script.
pub const UPLOT_JS: &str = include_str!("assets/uplot/uPlot.iife.min.js");
/// uPlot's style.
pub const UPLOT_CSS: &str = include_str!("assets/uplot/uPlot.min.css");
/// The licences of what the page includes.
pub const LICENSES: &str = concat!(
    "The explorer page of shotdamp includes uPlot 1.6.32 (https://github.com/leeoniya/uPlot), under this licence:\n\n",
    include_str!("assets/uplot/LICENSE")
);
