//! Text for the plots: plotters draws glyphs with ab_glyph and bundles no font, so the plot
//! tools load a TrueType file (`--font`, default DejaVu Sans where Debian installs it).

use plotters::style::FontStyle;

/// Where Debian's `fonts-dejavu-core` puts DejaVu Sans.
pub const DEFAULT_FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Registers the font that `--font FILE` in `args` names (or [`DEFAULT_FONT`]) as
/// "sans-serif".
pub fn register_from_args(args: &[String], usage: &str) -> Result<(), String> {
    let font = match args.iter().position(|a| a == "--font") {
        Some(i) => args.get(i + 1).ok_or(usage)?.clone(),
        None => DEFAULT_FONT.to_string(),
    };
    let bytes = std::fs::read(&font).map_err(|e| format!("font {font}: {e} (pass --font)"))?;
    plotters::style::register_font("sans-serif", FontStyle::Normal, Box::leak(bytes.into()))
        .map_err(|_| format!("{font} is not a TrueType font"))
}
