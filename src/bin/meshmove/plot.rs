//! PNG pictures with plotters' bitmap backend. No text is drawn (so no font library is needed):
//! captions and numbers live in results.csv, convergence.csv and docs/RESULTS.md.

use glam::DVec2;
use meshmove::Mesh;
use plotters::prelude::*;
use std::path::Path;

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
    fn contains(&self, p: DVec2) -> bool {
        p.x >= self.x0 && p.x <= self.x1 && p.y >= self.y0 && p.y <= self.y1
    }
}

/// Pixel rectangle (left, top, width, height).
type Rect = (i32, i32, i32, i32);

fn to_px(v: &View, r: Rect, p: DVec2) -> (i32, i32) {
    let sx = r.2 as f64 / (v.x1 - v.x0);
    let sy = r.3 as f64 / (v.y1 - v.y0);
    let s = sx.min(sy);
    (r.0 + ((p.x - v.x0) * s).round() as i32, r.1 + r.3 - ((p.y - v.y0) * s).round() as i32)
}

type Err = Box<dyn std::error::Error>;

fn draw_mesh<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    mesh: &Mesh,
    coords: &[DVec2],
    inverted: &[bool],
    view: &View,
    r: Rect,
    clip: bool,
) -> Result<(), Err>
where
    DB::ErrorType: 'static,
{
    let inside = |c: &[u32; 3]| !clip || c.iter().all(|&v| view.contains(coords[v as usize]));
    for (k, c) in mesh.cells().iter().enumerate() {
        if inverted[k] && inside(c) {
            let pts: Vec<(i32, i32)> = c.iter().map(|&v| to_px(view, r, coords[v as usize])).collect();
            area.draw(&Polygon::new(pts, RED.filled()))?;
        }
    }
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(3 * mesh.num_cells());
    for c in mesh.cells().iter().filter(|c| inside(c)) {
        for (a, b) in [(c[0], c[1]), (c[1], c[2]), (c[2], c[0])] {
            edges.push((a.min(b), a.max(b)));
        }
    }
    edges.sort_unstable();
    edges.dedup();
    let grey = RGBColor(40, 40, 40);
    for (a, b) in edges {
        let p = to_px(view, r, coords[a as usize]);
        let q = to_px(view, r, coords[b as usize]);
        area.draw(&PathElement::new(vec![p, q], grey.stroke_width(1)))?;
    }
    Ok(())
}

/// The deformed mesh, inverted cells filled red, `width` pixels wide; with `inset`, a zoomed
/// window drawn framed in the top-right corner (the boundary-layer cylinder).
pub fn mesh_png(
    path: &Path,
    mesh: &Mesh,
    coords: &[DVec2],
    inverted: &[bool],
    view: View,
    inset: Option<View>,
    width: u32,
) -> Result<(), Err> {
    let aspect = (view.y1 - view.y0) / (view.x1 - view.x0);
    let height = ((width as f64 * aspect).round() as u32).max(50);
    let mut buf = vec![0u8; 3 * (width * height) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        draw_mesh(&root, mesh, coords, inverted, &view, (0, 0, width as i32, height as i32), false)?;
        if let Some(iv) = inset {
            let side = (height.min(width) as f64 * 0.45) as i32;
            let r = (width as i32 - side - 4, 4, side, side);
            root.draw(&Rectangle::new([(r.0 - 2, r.1 - 2), (r.0 + r.2 + 2, r.1 + r.3 + 2)], WHITE.filled()))?;
            draw_mesh(&root, mesh, coords, inverted, &iv, r, true)?;
            root.draw(&Rectangle::new([(r.0 - 2, r.1 - 2), (r.0 + r.2 + 2, r.1 + r.3 + 2)], BLUE.stroke_width(2)))?;
            // The inset's window marked in the main view.
            let a = to_px(&view, (0, 0, width as i32, height as i32), DVec2::new(iv.x0, iv.y1));
            let b = to_px(&view, (0, 0, width as i32, height as i32), DVec2::new(iv.x1, iv.y0));
            root.draw(&Rectangle::new([a, b], BLUE.stroke_width(2)))?;
        }
        root.present()?;
    }
    save_png(path, &buf, width, height)
}

/// Semi-log plot of several series (one per colour) of positive values against their index:
/// decade grid lines in grey, no labels (the numbers are written to a CSV beside the picture).
pub fn semilog_png(path: &Path, series: &[(&[f64], RGBColor)], width: u32, height: u32) -> Result<(), Err> {
    let mut buf = vec![0u8; 3 * (width * height) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        let vals = series.iter().flat_map(|s| s.0.iter().copied()).filter(|v| *v > 0.0);
        let (lo, hi) = vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
        let (d0, d1) = (lo.log10().floor(), hi.log10().ceil().max(lo.log10().floor() + 1.0));
        let nmax = series.iter().map(|s| s.0.len()).max().unwrap_or(1).max(2) as f64;
        let (l, t, w, h) = (20, 20, width as i32 - 40, height as i32 - 40);
        let px = |i: f64, v: f64| {
            let x = l + ((i / (nmax - 1.0)) * w as f64).round() as i32;
            let y = t + h - (((v.log10() - d0) / (d1 - d0)) * h as f64).round() as i32;
            (x, y)
        };
        let mut d = d0;
        while d <= d1 + 0.5 {
            let y = px(0.0, 10f64.powf(d)).1;
            root.draw(&PathElement::new(vec![(l, y), (l + w, y)], RGBColor(210, 210, 210).stroke_width(1)))?;
            d += 1.0;
        }
        let mut i = 0.0;
        while i < nmax {
            let x = px(i, 10f64.powf(d0)).0;
            root.draw(&PathElement::new(vec![(x, t), (x, t + h)], RGBColor(235, 235, 235).stroke_width(1)))?;
            i += 10.0;
        }
        root.draw(&Rectangle::new([(l, t), (l + w, t + h)], BLACK.stroke_width(1)))?;
        for (s, colour) in series {
            let pts: Vec<(i32, i32)> =
                s.iter().enumerate().filter(|(_, v)| **v > 0.0).map(|(k, v)| px(k as f64, *v)).collect();
            root.draw(&PathElement::new(pts, colour.stroke_width(2)))?;
        }
        root.present()?;
    }
    save_png(path, &buf, width, height)
}

/// Writes an RGB buffer as PNG: indexed colour when it has at most 256 colours, best compression.
fn save_png(path: &Path, rgb: &[u8], width: u32, height: u32) -> Result<(), Err> {
    let mut palette: Vec<[u8; 3]> = Vec::new();
    let mut index = Vec::with_capacity(rgb.len() / 3);
    let mut map = std::collections::HashMap::new();
    for px in rgb.chunks_exact(3) {
        let c = [px[0], px[1], px[2]];
        let next = palette.len();
        let i = *map.entry(c).or_insert(next);
        if i == next {
            palette.push(c);
        }
        index.push(i);
    }
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut enc = png::Encoder::new(file, width, height);
    enc.set_compression(png::Compression::Best);
    if palette.len() <= 256 {
        enc.set_color(png::ColorType::Indexed);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_palette(palette.concat());
        let data: Vec<u8> = index.iter().map(|&i| i as u8).collect();
        enc.write_header()?.write_image_data(&data)?;
    } else {
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header()?.write_image_data(rgb)?;
    }
    Ok(())
}
