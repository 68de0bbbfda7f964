// errclass a.exr b.exr ref.exr [depth.exr]: relMSE delta (b - a) split by class
fn load(p: &str) -> image::Rgba32FImage { image::open(p).unwrap().to_rgba32f() }
fn e(p: [f32;4], q: [f32;4]) -> f64 { (0..3).map(|c| { let d = (p[c]-q[c]) as f64; d*d/((q[c] as f64).powi(2)+0.01) }).sum::<f64>()/3.0 }
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let (x, y, r) = (load(&a[1]), load(&a[2]), load(&a[3]));
    let dep = a.get(4).map(|p| load(p));
    let (w, h) = r.dimensions();
    let n = (w * h) as f64;
    let mut cls = std::collections::BTreeMap::<&str, (f64, f64, f64, usize)>::new();
    for j in 0..h { for i in 0..w {
        let (p, q, rr) = (x.get_pixel(i,j).0, y.get_pixel(i,j).0, r.get_pixel(i,j).0);
        let ea = e(p, rr); let eb = e(q, rr);
        // edge: depth ratio > 1.1 within the 3x3 (of the native depth)
        let mut edge = false;
        if let Some(d) = &dep {
            let c = d.get_pixel(i,j).0[0];
            for dy in -1i32..=1 { for dx in -1i32..=1 {
                let (u, v) = (i as i32 + dx, j as i32 + dy);
                if u < 0 || v < 0 || u >= w as i32 || v >= h as i32 { continue; }
                let o = d.get_pixel(u as u32, v as u32).0[0];
                if o > c * 1.1 || c > o * 1.1 { edge = true; }
            }}
        }
        let bright_on_dark = q[1] > rr[1] * 2.0 + 0.1;
        let dark_on_bright = q[1] < rr[1] * 0.5 - 0.05;
        let k = match (edge, bright_on_dark, dark_on_bright) {
            (true, true, _) => "edge bright>ref",
            (true, _, true) => "edge dark<ref",
            (true, _, _) => "edge other",
            (false, true, _) => "flat bright>ref",
            (false, _, true) => "flat dark<ref",
            _ => "flat other",
        };
        let t = cls.entry(k).or_insert((0.0, 0.0, 0.0, 0));
        t.0 += ea; t.1 += eb; t.2 += eb - ea; t.3 += 1;
    }}
    for (k, t) in cls { println!("{:18} px {:7}  a {:.5}  b {:.5}  delta {:.5}", k, t.3, t.0 / n, t.1 / n, t.2 / n); }
}
