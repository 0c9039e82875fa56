//! The embedded font.
//!
//! Plotters is built with its `ab_glyph` text backend, which reads no system
//! font: the font used to measure and draw text is compiled into the binary
//! (DejaVu Sans, `assets/fonts/`, see `DejaVu-LICENSE` there) and registered
//! once under the family name [`FONT_FAMILY`]. SVG output names that family,
//! so a viewer substitutes its own sans-serif face; PNG output is drawn with
//! DejaVu Sans itself.

use std::sync::OnceLock;

use plotters::style::{FontStyle, register_font};

use crate::error::{Error, Result};

/// Family name under which the embedded font is registered and which every
/// figure asks for.
pub const FONT_FAMILY: &str = "sans-serif";

/// The DejaVu Sans TrueType file, as compiled into the crate.
pub const DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Registers the embedded font with plotters; later calls do nothing.
///
/// Every function that draws calls this first, so users never need to.
pub fn register() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| register_font(FONT_FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok());
    if ok {
        Ok(())
    } else {
        Err(Error::invalid(
            "font",
            "assets/fonts/DejaVuSans.ttf (embedded)",
            "a TrueType font that ab_glyph can read",
        ))
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_embedded_font_registers_and_registering_again_is_harmless() {
        super::register().unwrap();
        super::register().unwrap();
    }
}
