//! `viewer.html`: one self-contained page (the template `viewer.html`
//! beside this file, all its JavaScript written here, no network) with the
//! frames inline as JSON.

use anyhow::Result;
use serde_json::json;

use super::gif_out::{time_decimals, time_unit};
use super::scene::{CAMERA_AZIMUTH, CAMERA_ELEVATION};
use super::{Movie, Settings};

/// The page's template; `__TIPPETOP_DATA__` is replaced by the data.
const TEMPLATE: &str = include_str!("viewer.html");

/// The marker in [`TEMPLATE`] replaced by the JSON data.
const DATA_MARKER: &str = "__TIPPETOP_DATA__";

/// The page for `movie`: the template with the frames, the trace and θ(t)
/// inline as JSON (safe inside a `<script>` element: `<`, `>` and `&`
/// escaped as `\u00XX`).
pub fn html(movie: &Movie, settings: &Settings) -> Result<String> {
    let t_last = movie.frames.last().map_or(1.0, |f| f.t);
    let (unit, uname) = time_unit(t_last);
    let f = &movie.frames;
    let data = json!({
        "title": movie.title,
        "R": movie.radius,
        "a": movie.offset,
        "stem": movie.stem.map(|(r2, d2)| [r2, d2]),
        "fps": movie.fps,
        "frame_dt": movie.frame_dt,
        "unit": uname,
        "unit_s": unit,
        "decimals": time_decimals(movie.frame_dt, unit),
        "width": settings.width,
        "height": settings.height,
        "azimuth": CAMERA_AZIMUTH,
        "elevation": CAMERA_ELEVATION,
        "t": f.iter().map(|x| x.t).collect::<Vec<_>>(),
        "theta": f.iter().map(|x| x.theta).collect::<Vec<_>>(),
        "spin": f.iter().map(|x| x.spin).collect::<Vec<_>>(),
        "com": f.iter().map(|x| x.com).collect::<Vec<_>>(),
        "q": f.iter().map(|x| x.q).collect::<Vec<_>>(),
        "contact": f.iter().map(|x| x.contact).collect::<Vec<_>>(),
        "force": f.iter().map(|x| x.force).collect::<Vec<_>>(),
        "force_max": movie.force_max,
        "scale_bar": [movie.scale_bar.0, movie.scale_bar.1.clone()],
        "trace": movie.trace,
        "theta_curve": movie.theta_curve,
    });
    let mut text = serde_json::to_string(&data)?;
    if text.contains(['<', '>', '&']) {
        text = text
            .replace('<', "\\u003c")
            .replace('>', "\\u003e")
            .replace('&', "\\u0026");
    }
    Ok(TEMPLATE.replacen(DATA_MARKER, &text, 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn template_has_one_marker_and_no_network() {
        assert_eq!(TEMPLATE.matches(DATA_MARKER).count(), 1);
        assert!(!TEMPLATE.contains("http://") && !TEMPLATE.contains("https://"));
    }
}
