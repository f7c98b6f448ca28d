//! Pictures of deformed 3D meshes: a plane section through the moved patch, each cut cell
//! drawn as its section polygon and filled by its volume ratio (deformed over original) on a
//! logarithmic blue–white–green scale with a colour bar, inverted cells red, the moved patch's
//! section blue. The caption says which plane, how many inverted cells the section shows
//! against the whole mesh's, and the whole mesh's cells of negative volume and smallest volume
//! ratio.

use crate::plot::{
    caption_height, draw_caption, font_px, register_font, save_png, to_px, Err, Rect, View, EDGE_COLOUR,
    INVERTED_COLOUR, PATCH_COLOUR,
};
use glam::DVec2;
use meshmove::mesh::{inverted_cells, signed_measures};
use meshmove::{Mesh, Motion};
use meshmove_cases::cut::{cell_sections, patch_section, plane_through_patch, section_axes, CellSection};
use plotters::prelude::*;
use std::path::Path;

/// The font family registered by `plot::register_font`.
const FONT: &str = "sans-serif";
const AXIS_NAMES: [&str; 3] = ["x", "y", "z"];
/// Volume ratios 2^-RANGE to 2^RANGE span the colour scale; beyond, the end colours.
const RANGE: f64 = 2.0;
const COMPRESSED: RGBColor = RGBColor(33, 102, 172);
const EXPANDED: RGBColor = RGBColor(0, 120, 60);
const NEUTRAL: RGBColor = RGBColor(247, 247, 247);

/// Colour steps per side of the scale: few enough distinct colours that the PNG's palette
/// (`plot::save_png`, the 256 most frequent colours) holds every one of them.
const STEPS: f64 = 8.0;

/// The colour of a cell of volume ratio `r` (valid cells: `r` > 0): log2(r) / RANGE rounded to
/// a multiple of 1 / STEPS, from blue (compressed) through near-white (1) to green (expanded).
pub fn ratio_colour(r: f64) -> RGBColor {
    let t = ((r.log2() / RANGE).clamp(-1.0, 1.0) * STEPS).round() / STEPS;
    let end = if t < 0.0 { COMPRESSED } else { EXPANDED };
    let f = t.abs();
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    RGBColor(mix(NEUTRAL.0, end.0), mix(NEUTRAL.1, end.1), mix(NEUTRAL.2, end.2))
}

/// The axis a 3D case's picture cuts across: the one the boundary moves least along (summed
/// |displacement| of the prescribed motion), so the section shows the motion; ties go to y, then
/// z, then x (a free surface moved in z is cut by y = const, a body moved in x and y by
/// z = const).
pub fn section_axis(mesh: &Mesh, motion: &Motion) -> usize {
    let values = motion.vertex_values(mesh);
    let sums: Vec<f64> = (0..3).map(|a| values.iter().skip(a).step_by(3).map(|d| d.abs()).sum()).collect();
    let mut best = 1;
    for a in [2, 0] {
        if sums[a] < sums[best] {
            best = a;
        }
    }
    best
}

/// Where the sections are drawn: the world window, its pixel rectangle, and whether only the
/// polygons entirely inside the window are drawn (an inset).
struct Frame {
    view: View,
    rect: Rect,
    clip: bool,
}

fn draw_sections<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    sections: &[CellSection],
    colours: &[RGBColor],
    highlight: &[[[f64; 2]; 2]],
    frame: &Frame,
) -> Result<(), Err>
where
    DB::ErrorType: 'static,
{
    let Frame { view, rect, clip } = frame;
    let pt = |p: &[f64; 2]| DVec2::new(p[0], p[1]);
    let inside = |poly: &[[f64; 2]]| !clip || poly.iter().all(|p| view.contains(pt(p)));
    let thin = sections.len() > 20_000;
    for (s, colour) in sections.iter().zip(colours).filter(|(s, _)| inside(&s.polygon)) {
        let px: Vec<(i32, i32)> = s.polygon.iter().map(|p| to_px(view, *rect, pt(p))).collect();
        area.draw(&Polygon::new(px.clone(), colour.filled()))?;
        if !thin || *clip {
            let mut closed = px;
            closed.push(closed[0]);
            area.draw(&PathElement::new(closed, EDGE_COLOUR.mix(0.6).stroke_width(1)))?;
        }
    }
    for seg in highlight.iter().filter(|s| inside(&s[..])) {
        let a = to_px(view, *rect, pt(&seg[0]));
        let b = to_px(view, *rect, pt(&seg[1]));
        area.draw(&PathElement::new(vec![a, b], PATCH_COLOUR.stroke_width(3)))?;
    }
    Ok(())
}

/// The colour bar in the band `rect`: the scale from 2^-RANGE to 2^RANGE with ticks at the
/// powers of two, its name, and the red of inverted cells.
fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    rect: Rect,
    fs: i32,
) -> Result<(), Err>
where
    DB::ErrorType: 'static,
{
    let (x0, y0, w, _) = rect;
    let (left, bar_w, bar_h) = (x0 + fs, w - 10 * fs, fs);
    let top = y0 + fs / 2;
    for k in 0..bar_w {
        let t = -RANGE + 2.0 * RANGE * (k as f64 + 0.5) / bar_w as f64;
        let c = ratio_colour(t.exp2());
        area.draw(&Rectangle::new([(left + k, top), (left + k + 1, top + bar_h)], c.filled()))?;
    }
    area.draw(&Rectangle::new([(left, top), (left + bar_w, top + bar_h)], BLACK.stroke_width(1)))?;
    let style = (FONT, fs * 9 / 10).into_font().color(&BLACK);
    for e in -(RANGE as i32)..=RANGE as i32 {
        let x = left + ((e as f64 + RANGE) / (2.0 * RANGE) * bar_w as f64).round() as i32;
        area.draw(&PathElement::new(vec![(x, top + bar_h), (x, top + bar_h + fs / 3)], BLACK.stroke_width(1)))?;
        let label = 2f64.powi(e).to_string();
        let dx = (label.len() as i32 * fs) / 4;
        area.draw(&Text::new(label, (x - dx, top + bar_h + fs / 2), style.clone()))?;
    }
    let name = "volume ratio, deformed / original (log scale)";
    area.draw(&Text::new(name, (left, top + bar_h + fs * 8 / 5), style.clone()))?;
    let rx = left + bar_w + 2 * fs;
    area.draw(&Rectangle::new([(rx, top), (rx + 2 * fs, top + bar_h)], INVERTED_COLOUR.filled()))?;
    area.draw(&Text::new("inverted", (rx + 5 * fs / 2, top), style))?;
    Ok(())
}

/// The inverted cells the section cuts (each counted once).
fn in_section(sections: &[CellSection], inverted: &[bool]) -> usize {
    let mut cut: Vec<usize> = sections.iter().map(|s| s.cell).filter(|&c| inverted[c]).collect();
    cut.sort_unstable();
    cut.dedup();
    cut.len()
}

/// The caption's line on inverted cells: how many the section shows against the whole mesh's.
fn inverted_line(shown: usize, total: usize, cells: usize) -> String {
    format!(
        "inverted (red; a corner Jacobian or volume ≤ 0): {shown} in this section, {total} in total of {cells} cells"
    )
}

/// The section picture of a deformed 3D mesh: `mesh` (the original) at `coords`, cut by the plane
/// normal to `axis` through the centroid of the original `moved_patch`, moved off the vertices
/// ([`plane_through_patch`]); `title`, then the inverted cells in the section and in the whole
/// mesh, the whole mesh's negative volumes and smallest volume ratio, the plane, and `extra`
/// lines. The
/// section of `moved_patch` is drawn blue; when it is small in the picture (a body in a large
/// domain), a framed inset of 1.5 times its size around it is drawn in the top-right corner.
pub fn section_png(
    path: &Path,
    (mesh, coords): (&Mesh, &[f64]),
    (title, extra): (String, &[String]),
    (axis, moved_patch): (usize, i32),
    width: u32,
) -> Result<(), Err> {
    register_font()?;
    let value = plane_through_patch(mesh, axis, moved_patch);
    let sections = cell_sections(mesh, coords, axis, value);
    let before = signed_measures(mesh, mesh.coords());
    let after = signed_measures(mesh, coords);
    let mut inverted = vec![false; mesh.num_cells()];
    inverted_cells(mesh, coords).into_iter().for_each(|c| inverted[c] = true);
    let count = inverted.iter().filter(|&&b| b).count();
    let negative = after.iter().filter(|a| a.partial_cmp(&&0.0) != Some(std::cmp::Ordering::Greater)).count();
    let min_ratio = after.iter().zip(&before).map(|(a, b)| a / b).fold(f64::INFINITY, f64::min);
    let colours: Vec<RGBColor> = sections
        .iter()
        .map(|s| if inverted[s.cell] { INVERTED_COLOUR } else { ratio_colour(after[s.cell] / before[s.cell]) })
        .collect();
    let highlight = patch_section(mesh, coords, moved_patch, axis, value);
    let [h, v] = section_axes(axis).map(|a| AXIS_NAMES[a]);
    let mut lines = vec![
        title,
        inverted_line(in_section(&sections, &inverted), count, mesh.num_cells()),
        format!("{negative} cells of negative volume, min volume ratio {min_ratio:.3} (whole mesh)"),
        format!(
            "section {} = {value:.4} ({} cells cut; {h} across, {v} up); blue: the moved patch",
            AXIS_NAMES[axis],
            sections.len()
        ),
    ];
    lines.extend_from_slice(extra);

    let pts: Vec<DVec2> = sections.iter().flat_map(|s| s.polygon.iter().map(|p| DVec2::new(p[0], p[1]))).collect();
    let view = View::around(&pts, 0.01);
    let hl: Vec<DVec2> = highlight.iter().flatten().map(|p| DVec2::new(p[0], p[1])).collect();
    let inset = (!hl.is_empty())
        .then(|| View::around(&hl, 0.0))
        .filter(|b| (b.x1 - b.x0).max(b.y1 - b.y0) < 0.1 * (view.x1 - view.x0).max(view.y1 - view.y0))
        .map(|b| {
            let c = DVec2::new(0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1));
            View::centred(c, 0.75 * (b.x1 - b.x0).max(b.y1 - b.y0))
        });
    if inset.is_some() {
        lines.push("inset (blue frame): 1.5 times the moved patch's size, around it".to_string());
    }

    let fs = font_px(width);
    let band = caption_height(lines.len(), fs);
    let aspect = (view.y1 - view.y0) / (view.x1 - view.x0);
    let main_h = ((width as f64 * aspect).round() as u32).max(50);
    let bar_band = fs * 9 / 2;
    let height = band as u32 + main_h + bar_band as u32;
    let mut buf = vec![0u8; 3 * (width * height) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        draw_caption(&root, &lines, fs)?;
        let main = (0, band, width as i32, main_h as i32);
        draw_sections(&root, &sections, &colours, &highlight, &Frame { view, rect: main, clip: false })?;
        if let Some(iv) = inset {
            let side = (main_h.min(width) as f64 * 0.45) as i32;
            let r = (width as i32 - side - 4, band + 4, side, side);
            let frame = [(r.0 - 2, r.1 - 2), (r.0 + r.2 + 2, r.1 + r.3 + 2)];
            root.draw(&Rectangle::new(frame, WHITE.filled()))?;
            draw_sections(&root, &sections, &colours, &highlight, &Frame { view: iv, rect: r, clip: true })?;
            root.draw(&Rectangle::new(frame, BLUE.stroke_width(2)))?;
            let a = to_px(&view, main, DVec2::new(iv.x0, iv.y1));
            let b = to_px(&view, main, DVec2::new(iv.x1, iv.y0));
            root.draw(&Rectangle::new([a, b], BLUE.stroke_width(2)))?;
        }
        draw_colour_bar(&root, (0, band + main_h as i32, width as i32, bar_band), fs)?;
        root.present()?;
    }
    save_png(path, &buf, width, height)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_caption_counts_the_inverted_cells_of_the_section_against_the_total() {
        let cut = |cell| CellSection { cell, polygon: vec![[0.0, 0.0]; 3] };
        let inverted = [true, false, true, true, false];
        // Cell 0 cut twice (counted once), cell 3 inverted but not cut.
        let sections = [cut(0), cut(1), cut(0), cut(2), cut(4)];
        assert_eq!(in_section(&sections, &inverted), 2);
        assert_eq!(
            inverted_line(2, 3, 5),
            "inverted (red; a corner Jacobian or volume ≤ 0): 2 in this section, 3 in total of 5 cells"
        );
    }
}
