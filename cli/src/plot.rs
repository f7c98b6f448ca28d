//! PNG pictures with plotters' bitmap backend. Text is drawn with Liberation Sans (SIL Open Font
//! License, `assets/fonts/`), compiled into the binary and registered with plotters' `ab_glyph`
//! renderer, so no system font library is needed. Every picture carries its own caption: what it
//! shows, the numbers that judge it, and what the colours mean.

use glam::DVec2;
use meshmove::Mesh;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::Once;

/// The font family name the pictures use (registered by [`register_font`]).
const FONT: &str = "sans-serif";
const FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/LiberationSans-Regular.ttf");

/// Colour of the inverted cells.
pub const INVERTED_COLOUR: RGBColor = RGBColor(220, 30, 30);
/// Colour of the highlighted edges (the moved patch or interface).
pub const PATCH_COLOUR: RGBColor = RGBColor(20, 80, 220);
pub(crate) const EDGE_COLOUR: RGBColor = RGBColor(40, 40, 40);

/// Registers the embedded font once per process (the pictures cannot draw text before).
pub(crate) fn register_font() -> Result<(), Err> {
    static ONCE: Once = Once::new();
    let mut result = Ok(());
    ONCE.call_once(|| {
        result = plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES)
            .map_err(|_| "the embedded font cannot be read".into());
    });
    result
}

/// Text height in pixels for a picture `width` pixels wide.
pub(crate) fn font_px(width: u32) -> i32 {
    (width as i32 / 42).clamp(11, 26)
}

/// A world window [x0, x1] × [y0, y1] mapped to a pixel rectangle.
#[derive(Clone, Copy)]
pub struct View {
    pub x0: f64,
    pub x1: f64,
    pub y0: f64,
    pub y1: f64,
}

impl View {
    pub fn around(pts: &[DVec2], margin: f64) -> View {
        let mut v = View { x0: f64::INFINITY, x1: f64::NEG_INFINITY, y0: f64::INFINITY, y1: f64::NEG_INFINITY };
        for p in pts {
            v.x0 = v.x0.min(p.x);
            v.x1 = v.x1.max(p.x);
            v.y0 = v.y0.min(p.y);
            v.y1 = v.y1.max(p.y);
        }
        let m = margin * (v.x1 - v.x0).max(v.y1 - v.y0);
        View { x0: v.x0 - m, x1: v.x1 + m, y0: v.y0 - m, y1: v.y1 + m }
    }
    pub fn centred(c: DVec2, half: f64) -> View {
        View { x0: c.x - half, x1: c.x + half, y0: c.y - half, y1: c.y + half }
    }
    pub fn contains(&self, p: DVec2) -> bool {
        p.x >= self.x0 && p.x <= self.x1 && p.y >= self.y0 && p.y <= self.y1
    }
}

/// What a mesh picture shows besides the mesh: its caption lines (the first is the title) and the
/// edges drawn highlighted (vertex pairs, e.g. a moved patch or an interface).
pub struct Annotation<'a> {
    pub lines: &'a [String],
    pub highlight: &'a [[u32; 2]],
}

/// Pixel rectangle (left, top, width, height).
pub(crate) type Rect = (i32, i32, i32, i32);

/// Where a mesh is drawn: the world window, the pixel rectangle it maps to, and whether only the
/// cells entirely inside the window are drawn (an inset).
struct Frame {
    view: View,
    rect: Rect,
    clip: bool,
}

pub(crate) fn to_px(v: &View, r: Rect, p: DVec2) -> (i32, i32) {
    let sx = r.2 as f64 / (v.x1 - v.x0);
    let sy = r.3 as f64 / (v.y1 - v.y0);
    let s = sx.min(sy);
    (r.0 + ((p.x - v.x0) * s).round() as i32, r.1 + r.3 - ((p.y - v.y0) * s).round() as i32)
}

pub(crate) type Err = Box<dyn std::error::Error>;

/// The mesh's edges in `frame`, inverted cells filled, highlighted edges on top.
fn draw_mesh<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    mesh: &Mesh,
    coords: &[DVec2],
    inverted: &[bool],
    highlight: &[[u32; 2]],
    frame: &Frame,
) -> Result<(), Err>
where
    DB::ErrorType: 'static,
{
    let Frame { view, rect: r, clip } = frame;
    let (view, r, clip) = (view, *r, *clip);
    let inside = |c: &[u32]| !clip || c.iter().all(|&v| view.contains(coords[v as usize]));
    for (k, &bad) in inverted.iter().enumerate() {
        let c = mesh.cell(k);
        if bad && inside(c) {
            let pts: Vec<(i32, i32)> = c.iter().map(|&v| to_px(view, r, coords[v as usize])).collect();
            area.draw(&Polygon::new(pts, INVERTED_COLOUR.filled()))?;
        }
    }
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(3 * mesh.num_cells());
    for c in (0..mesh.num_cells()).map(|k| mesh.cell(k)).filter(|c| inside(c)) {
        for k in 0..c.len() {
            let (a, b) = (c[k], c[(k + 1) % c.len()]);
            edges.push((a.min(b), a.max(b)));
        }
    }
    edges.sort_unstable();
    edges.dedup();
    for (a, b) in edges {
        let p = to_px(view, r, coords[a as usize]);
        let q = to_px(view, r, coords[b as usize]);
        area.draw(&PathElement::new(vec![p, q], EDGE_COLOUR.stroke_width(1)))?;
    }
    for e in highlight.iter().filter(|e| inside(&e[..])) {
        let p = to_px(view, r, coords[e[0] as usize]);
        let q = to_px(view, r, coords[e[1] as usize]);
        area.draw(&PathElement::new(vec![p, q], PATCH_COLOUR.stroke_width(3)))?;
    }
    Ok(())
}

/// Text height of caption line `k` (the title, line 0, is larger).
fn line_px(k: usize, fs: i32) -> i32 {
    if k == 0 {
        fs * 6 / 5
    } else {
        fs
    }
}

/// Height in pixels of a caption of `n` lines, as [`draw_caption`] draws it.
pub(crate) fn caption_height(n: usize, fs: i32) -> i32 {
    fs / 3 + (0..n).map(|k| line_px(k, fs) * 13 / 10).sum::<i32>() + fs / 3
}

/// Caption lines from the top of `area`, the first larger; returns the height used.
pub(crate) fn draw_caption<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    lines: &[String],
    fs: i32,
) -> Result<i32, Err>
where
    DB::ErrorType: 'static,
{
    let mut y = fs / 3;
    for (k, line) in lines.iter().enumerate() {
        let size = line_px(k, fs);
        area.draw(&Text::new(line.as_str(), (fs / 2, y), (FONT, size).into_font().color(&BLACK)))?;
        y += size * 13 / 10;
    }
    Ok(caption_height(lines.len(), fs))
}

/// The deformed mesh `width` pixels wide under its caption: inverted cells filled red, the
/// highlighted edges blue; `views.0` is the window drawn, and `views.1` a zoomed window drawn
/// framed in the top-right corner of the mesh (the boundary-layer cylinder), its place marked in
/// the main view.
pub fn mesh_png(
    path: &Path,
    (mesh, coords, inverted): (&Mesh, &[DVec2], &[bool]),
    (view, inset): (View, Option<View>),
    note: &Annotation,
    width: u32,
) -> Result<(), Err> {
    register_font()?;
    let fs = font_px(width);
    let band = caption_height(note.lines.len(), fs);
    let aspect = (view.y1 - view.y0) / (view.x1 - view.x0);
    let mesh_h = ((width as f64 * aspect).round() as u32).max(50);
    let height = mesh_h + band as u32;
    let mut buf = vec![0u8; 3 * (width * height) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        draw_caption(&root, note.lines, fs)?;
        let main = (0, band, width as i32, mesh_h as i32);
        draw_mesh(&root, mesh, coords, inverted, note.highlight, &Frame { view, rect: main, clip: false })?;
        if let Some(iv) = inset {
            let side = (mesh_h.min(width) as f64 * 0.45) as i32;
            let r = (width as i32 - side - 4, band + 4, side, side);
            let frame = [(r.0 - 2, r.1 - 2), (r.0 + r.2 + 2, r.1 + r.3 + 2)];
            root.draw(&Rectangle::new(frame, WHITE.filled()))?;
            draw_mesh(&root, mesh, coords, inverted, note.highlight, &Frame { view: iv, rect: r, clip: true })?;
            root.draw(&Rectangle::new(frame, BLUE.stroke_width(2)))?;
            let a = to_px(&view, main, DVec2::new(iv.x0, iv.y1));
            let b = to_px(&view, main, DVec2::new(iv.x1, iv.y0));
            root.draw(&Rectangle::new([a, b], BLUE.stroke_width(2)))?;
        }
        root.present()?;
    }
    save_png(path, &buf, width, height)
}

/// A deformed mesh's picture with its judgement drawn in: `title`, then "N inverted cells (red),
/// min area ratio R" measured against `mesh`'s own coordinates (the original mesh), then `extra`
/// lines. `views`: the window drawn (`None`: the whole deformed mesh) and an optional inset.
pub fn deformed_png(
    path: &Path,
    (mesh, coords): (&Mesh, &[f64]),
    (title, extra): (String, &[String]),
    highlight: &[[u32; 2]],
    (view, inset): (Option<View>, Option<View>),
    width: u32,
) -> Result<(), Err> {
    let before = meshmove::mesh::signed_measures(mesh, mesh.coords());
    let after = meshmove::mesh::signed_measures(mesh, coords);
    let mut inverted = vec![false; mesh.num_cells()];
    meshmove::mesh::inverted_cells(mesh, coords).into_iter().for_each(|c| inverted[c] = true);
    let coords = &xy(coords);
    let count = inverted.iter().filter(|&&b| b).count();
    let ratio = after.iter().zip(&before).map(|(a, b)| a / b).fold(f64::INFINITY, f64::min);
    let mut lines = vec![title, format!("{count} inverted cells (red), min area ratio {ratio:.3}")];
    lines.extend_from_slice(extra);
    let view = view.unwrap_or_else(|| View::around(coords, 0.01));
    let note = Annotation { lines: &lines, highlight };
    mesh_png(path, (mesh, coords, &inverted), (view, inset), &note, width)
}

/// The edges of `patch` (a boundary patch or an interface), for highlighting.
pub fn patch_edges(mesh: &Mesh, patch: i32) -> Vec<[u32; 2]> {
    mesh.patch_faces().filter(|e| e.patch == patch).map(|e| [e.vertices[0], e.vertices[1]]).collect()
}

/// Interleaved 2D positions as points.
pub fn xy(x: &[f64]) -> Vec<DVec2> {
    x.chunks_exact(2).map(|p| DVec2::new(p[0], p[1])).collect()
}

/// One curve of [`semilog_png`]: its legend name, values (one per x = 1, 2, …) and colour.
pub struct Series<'a> {
    pub name: &'a str,
    pub values: &'a [f64],
    pub colour: RGBColor,
}

/// A semi-log plot of positive values against their index (from 1): caption lines above, axes
/// with numbers and descriptions, one line per series and a legend naming them.
pub fn semilog_png(
    path: &Path,
    lines: &[String],
    (x_desc, y_desc): (&str, &str),
    series: &[Series],
    width: u32,
    height: u32,
) -> Result<(), Err> {
    register_font()?;
    let fs = font_px(width);
    let mut buf = vec![0u8; 3 * (width * height) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        let band = draw_caption(&root, lines, fs)?;
        let (_, plot_area) = root.split_vertically(band);
        let vals = series.iter().flat_map(|s| s.values.iter().copied()).filter(|v| *v > 0.0);
        let (lo, hi) = vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
        let (lo, hi) = if lo < hi { (lo, hi) } else { (0.1, 1.0) };
        let (y0, y1) = (10f64.powf(lo.log10().floor()), 10f64.powf(hi.log10().ceil()));
        let nmax = series.iter().map(|s| s.values.len()).max().unwrap_or(1).max(2) as f64;
        let mut chart = ChartBuilder::on(&plot_area)
            .margin(fs / 2)
            .margin_right(fs * 3 / 2)
            .x_label_area_size(fs * 5 / 2)
            .y_label_area_size(fs * 4)
            .build_cartesian_2d(1f64..nmax, (y0..y1).log_scale())?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .label_style((FONT, fs * 9 / 10))
            .axis_desc_style((FONT, fs))
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        for s in series {
            let colour = s.colour;
            let pts = s.values.iter().enumerate().filter(|(_, v)| **v > 0.0).map(|(k, v)| ((k + 1) as f64, *v));
            chart
                .draw_series(LineSeries::new(pts, colour.stroke_width(2)))?
                .label(s.name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + fs, y)], colour.stroke_width(2)));
        }
        chart
            .configure_series_labels()
            .label_font((FONT, fs))
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
        root.present()?;
    }
    save_png(path, &buf, width, height)
}

/// Writes an RGB buffer as PNG with indexed colour and best compression: the 256 most frequent
/// colours form the palette and any other (anti-aliased text edges) takes its nearest entry.
pub(crate) fn save_png(path: &Path, rgb: &[u8], width: u32, height: u32) -> Result<(), Err> {
    let mut counts: std::collections::HashMap<[u8; 3], usize> = std::collections::HashMap::new();
    for px in rgb.chunks_exact(3) {
        *counts.entry([px[0], px[1], px[2]]).or_default() += 1;
    }
    let mut by_count: Vec<([u8; 3], usize)> = counts.into_iter().collect();
    by_count.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let palette: Vec<[u8; 3]> = by_count.iter().take(256).map(|c| c.0).collect();
    let mut index_of: std::collections::HashMap<[u8; 3], u8> =
        palette.iter().enumerate().map(|(i, c)| (*c, i as u8)).collect();
    let nearest = |c: [u8; 3]| {
        let d = |p: &[u8; 3]| (0..3).map(|k| (p[k] as i32 - c[k] as i32).pow(2)).sum::<i32>();
        (0..palette.len()).min_by_key(|&i| d(&palette[i])).unwrap_or(0) as u8
    };
    let data: Vec<u8> = rgb
        .chunks_exact(3)
        .map(|px| {
            let c = [px[0], px[1], px[2]];
            *index_of.entry(c).or_insert_with(|| nearest(c))
        })
        .collect();
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut enc = png::Encoder::new(file, width, height);
    enc.set_compression(png::Compression::Best);
    enc.set_color(png::ColorType::Indexed);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_palette(palette.concat());
    enc.write_header()?.write_image_data(&data)?;
    Ok(())
}
