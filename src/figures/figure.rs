//! The [`Figure`] trait and [`save`]: one figure drawn on any plotters
//! backend, written as SVG or PNG by file extension, atomically.

use std::fs;
use std::io;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::{
    BitMapBackend, DrawingArea, DrawingAreaErrorKind, DrawingBackend, IntoDrawingArea, SVGBackend,
};

use super::font;
use super::raster::Raster;
use super::style::Style;
use crate::error::{Error, Result};

/// What drawing on a plotters backend `DB` returns.
pub type DrawResult<DB> =
    std::result::Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// A figure that can be drawn on any plotters backend.
pub trait Figure {
    /// Printed size (width, height) in inches.
    fn size_in(&self) -> (f64, f64);

    /// Draws the figure on `root`, which covers the whole canvas, taking
    /// sizes, fonts and colours from `style`.
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: &Style,
    ) -> DrawResult<DB>;
}

/// Output formats, chosen by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Scalable vector graphics (`.svg`, or no extension).
    Svg,
    /// Portable network graphics (`.png`), at [`PNG_PX_PER_IN`](super::style::PNG_PX_PER_IN).
    Png,
}

impl Format {
    /// The format named by `path`'s extension (case-insensitive): `.svg` or
    /// none gives [`Format::Svg`], `.png` gives [`Format::Png`], anything else
    /// an [`Error::InvalidParameter`] on field `plot` naming the file.
    ///
    /// ```
    /// use rockfrag::figures::Format;
    /// use std::path::Path;
    /// assert_eq!(Format::from_path(Path::new("fig.PNG")).unwrap(), Format::Png);
    /// assert_eq!(Format::from_path(Path::new("fig")).unwrap(), Format::Svg);
    /// assert!(Format::from_path(Path::new("fig.pdf")).is_err());
    /// ```
    pub fn from_path(path: &Path) -> Result<Format> {
        let Some(ext) = path.extension() else {
            return Ok(Format::Svg);
        };
        match ext.to_str().map(str::to_ascii_lowercase).as_deref() {
            Some("svg") => Ok(Format::Svg),
            Some("png") => Ok(Format::Png),
            _ => Err(Error::invalid(
                "plot",
                path.display().to_string(),
                "a file name ending in .svg (the default) or .png",
            )),
        }
    }

    /// Lower-case file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Png => "png",
        }
    }

    /// The style at this format's resolution.
    pub fn style(self) -> Style {
        match self {
            Format::Svg => Style::SVG,
            Format::Png => Style::PNG,
        }
    }
}

/// Draws `figure` and writes it to `path` in the format its extension names
/// (see [`Format::from_path`]; a PNG through the bitmap backend with its
/// wide polylines split at sharp turns, which plotters alone spikes),
/// atomically: the figure is written to a
/// temporary file in the same directory and renamed over `path` only once
/// complete.
///
/// Errors: [`Error::InvalidParameter`] for an unsupported extension,
/// [`Error::Io`] (naming `path`) if the file cannot be written or drawing
/// fails.
pub fn save<F: Figure + ?Sized>(figure: &F, path: &Path) -> Result<()> {
    let format = Format::from_path(path)?;
    font::register()?;
    let style = format.style();
    let size = style.canvas(figure.size_in());
    let io_err = |source: io::Error| Error::Io {
        path: path.to_path_buf(),
        source,
    };

    // The temporary file keeps the extension: the PNG encoder is chosen by it.
    crate::io_util::write_atomic_path(path, |tmp| match format {
        Format::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                figure.draw(&root, &style).map_err(drawing_error)?;
                root.present().map_err(drawing_error)?;
            }
            fs::write(tmp, svg)
        }
        Format::Png => {
            // Creating the file first reports a missing directory or a
            // permission problem as the I/O error it is; the backend then
            // overwrites it.
            fs::File::create(tmp)?;
            // wide polylines split at sharp turns (see `raster`)
            let root = Raster(BitMapBackend::new(tmp, size)).into_drawing_area();
            figure.draw(&root, &style).map_err(drawing_error)?;
            root.present().map_err(drawing_error)
        }
    })
    .map_err(io_err)
}

/// Wraps a plotters error as an I/O error (plotters reports file and encoding
/// failures through its own error type).
fn drawing_error<E: std::error::Error + Send + Sync + 'static>(
    err: DrawingAreaErrorKind<E>,
) -> io::Error {
    io::Error::other(format!("drawing the figure failed: {err}"))
}
