//! Pictures of results as SVG (written by hand: a heatmap and line charts need no more),
//! and PNG by rendering that SVG with resvg, which `yokai replay --png` uses too.

use anyhow::Context;
use std::fmt::Write;

/// Text safe inside SVG elements.
pub fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Sequential colour from pale yellow (the lowest value, `t` = 0) to dark blue (the
/// highest, `t` = 1), so that differences show whatever the range of R.
fn sequential(t: f64) -> String {
    let t = t.clamp(0.0, 1.0);
    let (lo, hi) = ((255.0, 247.0, 188.0), (37.0, 52.0, 148.0));
    let mix = |a: f64, b: f64| (a + (b - a) * t) as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        mix(lo.0, hi.0),
        mix(lo.1, hi.1),
        mix(lo.2, hi.2)
    )
}

/// Size in pixels of the heatmap of `n` policies under `title`.
pub fn heatmap_size(n: usize, title: &str) -> (usize, usize) {
    let width = (LABEL + n * CELL + 20).max(20 + 9 * title.chars().count());
    (width, 60 + n * CELL + LABEL)
}

const CELL: usize = 64;
const LABEL: usize = 170;

/// The cross-play matrix as a heatmap: entry (i, j) is `values[i][j]` (R of policies i and
/// j together), the diagonal is self-play.
pub fn heatmap_svg(title: &str, names: &[String], values: &[Vec<f64>]) -> String {
    let n = names.len();
    let (w, h) = heatmap_size(n, title);
    let lo = values.iter().flatten().fold(f64::MAX, |m, &v| m.min(v));
    let hi = values.iter().flatten().fold(f64::MIN, |m, &v| m.max(v));
    let shade = |v: f64| sequential(if hi > lo { (v - lo) / (hi - lo) } else { 0.5 });
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" \
         font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"10\" y=\"24\" font-size=\"15\" font-weight=\"bold\">{}</text>\n",
        escape(title)
    );
    let top = 60;
    for (i, row) in values.iter().enumerate() {
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>",
            LABEL - 8,
            top + i * CELL + CELL / 2 + 4,
            escape(&names[i])
        );
        for (j, &v) in row.iter().enumerate() {
            let (x, y) = (LABEL + j * CELL, top + i * CELL);
            let _ = writeln!(
                s,
                "<rect class=\"cell\" data-row=\"{i}\" data-col=\"{j}\" data-value=\"{v:.3}\" x=\"{x}\" y=\"{y}\" \
                 width=\"{CELL}\" height=\"{CELL}\" fill=\"{}\" stroke=\"#fff\"/>\
                 <text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"{}\">{v:.2}</text>",
                shade(v),
                x + CELL / 2,
                y + CELL / 2 + 4,
                if hi > lo && (v - lo) / (hi - lo) > 0.55 { "white" } else { "black" }
            );
        }
    }
    for (j, name) in names.iter().enumerate() {
        let (x, y) = (LABEL + j * CELL + CELL / 2, top + n * CELL + 10);
        let _ = writeln!(
            s,
            "<text x=\"{x}\" y=\"{y}\" text-anchor=\"end\" transform=\"rotate(-45 {x} {y})\">{}</text>",
            escape(name)
        );
    }
    s.push_str("</svg>\n");
    s
}

/// One line of a chart.
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

const PALETTE: [&str; 12] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf", "#393b79", "#637939",
];

/// A line chart of `series`.
pub fn lines_svg(title: &str, x_label: &str, y_label: &str, series: &[Series]) -> String {
    // The legend sits right of the plot: wide enough for its longest label.
    let longest = series
        .iter()
        .map(|s| s.label.chars().count())
        .max()
        .unwrap_or(0);
    let right = (30.0 + 7.0 * longest as f64).max(160.0);
    let (w, h) = (560.0 + right, 420.0);
    let (left, top, bottom) = (70.0, 40.0, 50.0);
    let all = series.iter().flat_map(|s| s.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    if x1 - x0 < 1e-9 {
        x1 = x0 + 1.0;
    }
    if y1 - y0 < 1e-9 {
        (y0, y1) = (y0 - 1.0, y1 + 1.0);
    }
    let px = |x: f64| left + (x - x0) / (x1 - x0) * (w - left - right);
    let py = |y: f64| h - bottom - (y - y0) / (y1 - y0) * (h - top - bottom);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" \
         font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"{left}\" y=\"22\" font-size=\"15\" font-weight=\"bold\">{}</text>\n\
         <rect x=\"{left}\" y=\"{top}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#444\"/>\n",
        escape(title),
        w - left - right,
        h - top - bottom
    );
    // Enough decimals that the five y labels differ (a belief's 0.015-nat steps need 3).
    let digits = (2.0f64).max((-((y1 - y0) / 4.0).log10()).ceil() + 1.0) as usize;
    for k in 0..=4 {
        let y = y0 + (y1 - y0) * k as f64 / 4.0;
        let x = x0 + (x1 - x0) * k as f64 / 4.0;
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{y:.digits$}</text>\
             <line x1=\"{left}\" x2=\"{}\" y1=\"{py}\" y2=\"{py}\" stroke=\"#eee\"/>\
             <text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
            left - 6.0,
            py(y) + 4.0,
            w - right,
            px(x),
            h - bottom + 18.0,
            short_number(x),
            py = py(y)
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\
         <text x=\"16\" y=\"{}\" transform=\"rotate(-90 16 {})\" text-anchor=\"middle\">{}</text>",
        (left + w - right) / 2.0,
        h - 10.0,
        escape(x_label),
        (top + h - bottom) / 2.0,
        (top + h - bottom) / 2.0,
        escape(y_label)
    );
    for (k, series) in series.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let points: Vec<String> = series
            .points
            .iter()
            .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
            .collect();
        let _ = writeln!(
            s,
            "<polyline class=\"series\" data-label=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.8\" points=\"{}\"/>\
             <rect x=\"{}\" y=\"{}\" width=\"12\" height=\"3\" fill=\"{colour}\"/>\
             <text x=\"{}\" y=\"{}\">{}</text>",
            escape(&series.label),
            points.join(" "),
            w - right + 10.0,
            top + 10.0 + 16.0 * k as f64,
            w - right + 26.0,
            top + 14.0 + 16.0 * k as f64,
            escape(&series.label)
        );
    }
    s.push_str("</svg>\n");
    s
}

fn short_number(x: f64) -> String {
    if x.abs() >= 1e9 {
        format!("{:.1}G", x / 1e9)
    } else if x.abs() >= 1e6 {
        format!("{:.1}M", x / 1e6)
    } else if x.abs() >= 1e3 {
        format!("{:.0}k", x / 1e3)
    } else {
        format!("{x:.0}")
    }
}

/// Centred moving average over `window` points, so that noisy per-update metrics read as a
/// curve.
pub fn smooth(points: &[(f64, f64)], window: usize) -> Vec<(f64, f64)> {
    let half = window / 2;
    (0..points.len())
        .map(|i| {
            let lo = i.saturating_sub(half);
            let hi = (i + half + 1).min(points.len());
            let mean = points[lo..hi].iter().map(|p| p.1).sum::<f64>() / (hi - lo) as f64;
            (points[i].0, mean)
        })
        .collect()
}

/// The system's fonts, loaded once per process (a scan of the font directories), with
/// `sans-serif` mapped to a sans face that exists (fontdb maps it to Arial, which Linux
/// machines rarely have). Without any font, PNGs have no text.
pub fn system_fonts() -> std::sync::Arc<resvg::usvg::fontdb::Database> {
    static FONTS: std::sync::OnceLock<std::sync::Arc<resvg::usvg::fontdb::Database>> =
        std::sync::OnceLock::new();
    FONTS
        .get_or_init(|| std::sync::Arc::new(load_fonts()))
        .clone()
}

fn load_fonts() -> resvg::usvg::fontdb::Database {
    let mut db = resvg::usvg::fontdb::Database::new();
    db.load_system_fonts();
    let families: Vec<String> = db
        .faces()
        .filter_map(|f| f.families.first().map(|(name, _)| name.clone()))
        .collect();
    match families
        .iter()
        .find(|f| f.contains("Sans") && !f.contains("Mono"))
        .or(families.first())
    {
        Some(family) => db.set_sans_serif_family(family.clone()),
        None => eprintln!(
            "warning: no system font found, so PNG pictures have no text \
             (install e.g. fonts-dejavu-core, or use the SVG files)"
        ),
    }
    db
}

/// Rasterise an SVG picture to PNG bytes.
pub fn png(
    svg: &str,
    fonts: std::sync::Arc<resvg::usvg::fontdb::Database>,
) -> anyhow::Result<Vec<u8>> {
    let options = resvg::usvg::Options {
        fontdb: fonts,
        ..Default::default()
    };
    let tree = resvg::usvg::Tree::from_str(svg, &options).context("svg")?;
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height())
        .context("the picture has no area")?;
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    pixmap.encode_png().context("png")
}

/// Write `NAME.svg` and `NAME.png` into `dir`.
pub fn write_both(dir: &std::path::Path, name: &str, svg: &str) -> anyhow::Result<()> {
    let write = |file: String, bytes: &[u8]| {
        let path = dir.join(file);
        std::fs::write(&path, bytes).with_context(|| format!("cannot write {}", path.display()))
    };
    write(format!("{name}.svg"), svg.as_bytes())?;
    let fonts = system_fonts();
    write(format!("{name}.png"), &png(svg, fonts)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heatmap_has_one_cell_per_entry_and_renders_at_its_size() {
        let names: Vec<String> = vec!["a".into(), "b".into(), "c".into()];
        let values = vec![vec![1.0, -2.0, 0.5]; 3];
        let svg = heatmap_svg("xp", &names, &values);
        assert_eq!(svg.matches("class=\"cell\"").count(), 9);
        assert!(svg.contains("data-row=\"0\" data-col=\"1\" data-value=\"-2.000\""));
        let bytes = png(
            &svg,
            std::sync::Arc::new(resvg::usvg::fontdb::Database::new()),
        )
        .unwrap();
        let image = resvg::tiny_skia::Pixmap::decode_png(&bytes).unwrap();
        let (w, h) = heatmap_size(3, "xp");
        assert_eq!((image.width() as usize, image.height() as usize), (w, h));
        // The lowest entry is the palest, the highest the darkest.
        assert_eq!(sequential(0.0), "#fff7bc");
        assert_eq!(sequential(1.0), "#253494");
        assert!(svg.contains(
            "data-value=\"-2.000\" x=\"234\" y=\"60\" width=\"64\" height=\"64\" fill=\"#fff7bc\""
        ));
    }

    #[test]
    fn chart_has_a_line_per_series_and_smoothing_keeps_means() {
        let series = vec![
            Series {
                label: "seed 0".into(),
                points: vec![(0.0, 1.0), (10.0, 2.0)],
            },
            Series {
                label: "seed 1".into(),
                points: vec![(0.0, -1.0), (10.0, 0.0)],
            },
        ];
        let svg = lines_svg("R", "environment steps", "return", &series);
        assert_eq!(svg.matches("class=\"series\"").count(), 2);
        let s = smooth(&[(0.0, 0.0), (1.0, 3.0), (2.0, 6.0)], 3);
        assert_eq!(s, vec![(0.0, 1.5), (1.0, 3.0), (2.0, 4.5)]);
    }
}
