//! `solari`: the Solari workspace's command-line tool.
//!
//! - `solari render [SCENE] --view albedo|normal|depth|instance --size WxH --out FILE.png`
//! - `solari render [SCENE] --mode reference --spp N [--max-bounces N] --out FILE.exr`
//! - `solari render [SCENE] --mode realtime --frames N [--camera-path orbit] --out FILE.png`
//! - `solari soak [SCENE] --frames N --camera-path orbit --toggle-lights K`
//! - `solari view [SCENE] [--size WxH] [--frames N --screenshot FILE.png]`
//! - `solari info [SCENE] [--json]`
//! - `solari compare TEST REFERENCE [--heatmap OUT.png] [--mask-emitters SCENE] [--json]`
//! - `solari bench-rays [SCENE | --heightfield N] [--json]`
//! - `solari bench-di [SCENE] --candidates 1,8,32 --tiles 32x256,128x1024 --reference REF.exr`
//! - `solari bench-cache [SCENE] --cell-sizes 0.1,0.25 --budgets 40000 --reference REF.exr`
//! - `solari bench-denoise [SCENE] --frames 64 --iterations 1,3,5 --reference REF.exr`
//!
//! With no SCENE the built-in Cornell box is used. Every argument and path is checked before
//! any work starts; a failure exits with status 1 (2 for arguments clap refuses) and leaves
//! no partial output.

mod bench;
mod bench_cache;
mod bench_denoise;
mod bench_di;
mod bench_io;
mod compare;
mod info;
mod realtime_cmd;
mod render;
mod soak;
mod view;
mod view_overlay;

use clap::Parser;
use solari_app::cli::{Cli, Command};

fn main() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let args = Cli::parse();
    let result = args.check().and_then(|()| match &args.command {
        Command::Render(a) => render::run(a),
        Command::Info(a) => info::run(a),
        Command::BenchRays(a) => bench::run(a),
        Command::Compare(a) => compare::run(a),
        Command::BenchDi(a) => bench_di::run(a),
        Command::BenchCache(a) => bench_cache::run(a),
        Command::BenchDenoise(a) => bench_denoise::run(a),
        Command::Soak(a) => soak::run(a),
        Command::View(a) => view::run(a),
    });
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
