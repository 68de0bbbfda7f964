//! Command-line knobs reach the renderer's settings (parsed in-process, no GPU).

use clap::Parser;
use solari_app::cli::{Cli, Command};
use solari_renderer::FrameView;

fn di(args: &[&str]) -> (bool, bool) {
    let argv = [&["solari", "render", "--mode", "realtime"], args].concat();
    let cli = Cli::try_parse_from(argv).expect("parses");
    let Command::Render(r) = cli.command else {
        panic!("render");
    };
    let s = r.realtime.settings(FrameView::Lit).expect("valid settings");
    (s.di.temporal, s.di.spatial)
}

#[test]
fn di_reuse_chooses_the_reuse_steps() {
    assert_eq!(di(&[]), (true, true), "default: both reuse steps");
    assert_eq!(di(&["--di-reuse", "all"]), (true, true));
    assert_eq!(di(&["--di-reuse", "temporal"]), (true, false));
    assert_eq!(di(&["--di-reuse", "spatial"]), (false, true));
    assert_eq!(di(&["--di-reuse", "none"]), (false, false));
    assert!(
        Cli::try_parse_from(["solari", "render", "--di-reuse", "some"]).is_err(),
        "unknown reuse names are refused"
    );
}
