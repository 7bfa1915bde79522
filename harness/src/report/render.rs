//! Renders one figure twice: as SVG (the page shows these; text stays text) and as PNG
//! (plotters' bitmap backend, encoded with the `png` crate), from the same drawing code.
//!
//! Text is laid out with plotters' `ab_glyph` feature, which needs no system font
//! machinery (fontconfig, font-kit): the font is read from a file at run time and
//! registered as "sans-serif". The file is DejaVu Sans from Debian's
//! `fonts-dejavu-core` (installed by `scripts/setup.sh`), or `HARNESS_FONT`.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::report::ReportError;

/// Where Debian's `fonts-dejavu-core` puts DejaVu Sans.
pub const DEFAULT_FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// A figure that can draw itself on any plotters backend.
pub trait Figure {
    /// Draws the whole figure on `root` (already filled white); errors as text.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// The font file: `HARNESS_FONT` if set, else [`DEFAULT_FONT`].
pub fn font_path() -> PathBuf {
    std::env::var_os("HARNESS_FONT")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(DEFAULT_FONT))
}

/// Registers the font once per process; the error says which file is missing.
pub fn ensure_font() -> Result<(), ReportError> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    let path = font_path();
    let result = DONE.get_or_init(|| {
        let bytes = std::fs::read(&path).map_err(|e| e.to_string())?;
        // plotters keeps registered fonts for the whole process.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
            .map_err(|_| "not a usable TrueType/OpenType font".to_string())
    });
    result.clone().map_err(|message| ReportError::Font {
        path,
        message: format!(
            "{message} (install fonts-dejavu-core: scripts/setup.sh, or set HARNESS_FONT)"
        ),
    })
}

fn plot_error(path: &Path, message: impl std::fmt::Display) -> ReportError {
    ReportError::Plot {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

/// Draws `figure` into `svg` and `png`, both `size` pixels.
pub fn render(
    figure: &impl Figure,
    size: (u32, u32),
    svg: &Path,
    png: &Path,
) -> Result<(), ReportError> {
    ensure_font()?;
    {
        let root = SVGBackend::new(svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_error(svg, e))?;
        figure.draw(&root).map_err(|e| plot_error(svg, e))?;
        root.present().map_err(|e| plot_error(svg, e))?;
    }
    let mut rgb = vec![0u8; 3 * size.0 as usize * size.1 as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_error(png, e))?;
        figure.draw(&root).map_err(|e| plot_error(png, e))?;
        root.present().map_err(|e| plot_error(png, e))?;
    }
    write_png(png, size, &rgb)
}

/// Encodes an RGB8 buffer as a PNG file.
fn write_png(path: &Path, (w, h): (u32, u32), rgb: &[u8]) -> Result<(), ReportError> {
    let io = |source: std::io::Error| ReportError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::create(path).map_err(io)?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(|e| plot_error(path, e))?;
    writer
        .write_image_data(rgb)
        .map_err(|e| plot_error(path, e))?;
    writer.finish().map_err(|e| plot_error(path, e))
}
