//! `solari`: the Solari workspace's command-line tool.
//!
//! - `solari render [SCENE] --view albedo|normal|depth|instance --size WxH --out FILE.png`
//! - `solari render [SCENE] --mode reference --spp N [--max-bounces N] --out FILE.png`
//! - `solari render [SCENE] --mode realtime --frames N [--camera-path orbit] --out FILE.png`
//! - `solari info [SCENE] [--json]`
//! - `solari compare TEST REFERENCE [--heatmap OUT.png] [--mask-emitters SCENE] [--json]`
//! - `solari bench-rays [SCENE | --heightfield N] [--json]`
//! - `solari bench-di [SCENE] --candidates 1,8,32 --tiles 32x256,128x1024 --reference REF.exr`
//! - `solari bench-cache [SCENE] --cell-sizes 0.1,0.25 --budgets 40000 --reference REF.exr`
//! - `solari bench-denoise [SCENE] --frames 64 --iterations 1,3,5 --reference REF.exr`
//!
//! With no SCENE the built-in Cornell box is used.

mod bench;
mod bench_cache;
mod bench_denoise;
mod bench_di;
mod bench_io;
mod cli;
mod compare;
mod info;
mod realtime_cmd;
mod render;

use clap::Parser;

fn main() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let args = cli::Cli::parse();
    let result = match args.command {
        cli::Command::Render(a) => render::run(&a),
        cli::Command::Info(a) => info::run(&a),
        cli::Command::BenchRays(a) => bench::run(&a),
        cli::Command::Compare(a) => compare::run(&a),
        cli::Command::BenchDi(a) => bench_di::run(&a),
        cli::Command::BenchCache(a) => bench_cache::run(&a),
        cli::Command::BenchDenoise(a) => bench_denoise::run(&a),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
