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

/// What every plot tool starts from, `CSV OUT.png [--font FONT.ttf]` on its command line: the
/// font registered, the CSV's text and path, and the output path. `usage` is the error when
/// the arguments are missing.
pub struct PlotInput {
    /// The CSV file's path, for messages.
    pub csv: String,
    /// The CSV file's text.
    pub text: String,
    /// Where the PNG goes.
    pub out: String,
}

impl PlotInput {
    /// Reads the process's arguments (see [`PlotInput`]).
    pub fn from_args(usage: &str) -> Result<Self, String> {
        let args: Vec<String> = std::env::args().skip(1).collect();
        let (csv, out) = match args.as_slice() {
            [c, o, ..] => (c.clone(), o.clone()),
            _ => return Err(usage.into()),
        };
        register_from_args(&args, usage)?;
        let text = std::fs::read_to_string(&csv).map_err(|e| format!("{csv}: {e}"))?;
        Ok(Self { csv, text, out })
    }

    /// Runs a plot tool's `run`, printing its error and exiting with status 1 on failure.
    pub fn exit_on_error(run: fn() -> Result<(), String>) {
        if let Err(e) = run() {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
