//! Mutators: byte flips, insertions, deletions and truncation of the raw file; structural
//! mutations of the glTF JSON (numbers set to huge, negative, overflowing-to-infinity and
//! out-of-range index and count values, strings to hostile URIs, values of the wrong type,
//! array entries dropped or duplicated, glTF keys added or removed); and corruption of the
//! binary payloads embedded as data URIs (floats set to NaN, infinities, 1e38).

use base64::Engine as _;
use rand::Rng;
use serde_json::{Value, json};

/// Numbers that break things: boundaries of u8/u16/u32/i32/f32, overflow to infinity, tiny.
const NUMBERS: &[f64] = &[
    0.0,
    -1.0,
    1.0,
    2.0,
    3.0,
    4.0,
    255.0,
    256.0,
    65535.0,
    65536.0,
    2147483647.0,
    2147483648.0,
    4294967295.0,
    4294967296.0,
    9007199254740992.0,
    1.8446744073709552e19,
    -9.223372036854776e18,
    1e39,
    -1e39,
    1e308,
    3.4e38,
    1e-45,
    0.5,
    -0.0,
];

/// Strings that break URI handling, parsers and lookups.
const STRINGS: &[&str] = &[
    "",
    ".",
    "..",
    "../x.bin",
    "../../../../../../etc/hostname",
    "/etc/hostname",
    "/dev/zero",
    "/dev/urandom",
    "file:///etc/passwd",
    "http://example.invalid/a.bin",
    "%",
    "%é.bin",
    "%2e%2e/%2e%2e/x",
    "%00",
    "data:",
    "data:application/octet-stream;base64,",
    "data:application/octet-stream;base64,@@@@",
    "data:image/png;base64,iVBORw0KGgo=",
    "C:\\windows\\x.bin",
    "sub/../x.bin",
    "\u{0}",
    "é",
    "SCALAR",
    "VEC2",
    "VEC3",
    "VEC4",
    "MAT4",
    "BOGUS",
    "image/png",
    "image/jpeg",
    "KHR_draco_mesh_compression",
    "KHR_lights_punctual",
];

/// glTF keys worth adding where they do not belong (or removing where they do).
const KEYS: &[&str] = &[
    "byteStride",
    "byteOffset",
    "byteLength",
    "count",
    "bufferView",
    "buffer",
    "componentType",
    "normalized",
    "type",
    "min",
    "max",
    "sparse",
    "mode",
    "indices",
    "material",
    "attributes",
    "targets",
    "children",
    "mesh",
    "camera",
    "matrix",
    "scale",
    "rotation",
    "translation",
    "uri",
    "mimeType",
    "source",
    "sampler",
    "texCoord",
    "index",
    "extensions",
    "extensionsRequired",
    "scene",
    "nodes",
    "yfov",
    "znear",
    "zfar",
    "aspectRatio",
    "emissiveFactor",
    "baseColorFactor",
    "POSITION",
    "NORMAL",
    "TANGENT",
    "TEXCOORD_0",
];

const COMPONENT_TYPES: &[f64] = &[5120.0, 5121.0, 5122.0, 5123.0, 5125.0, 5126.0, 0.0, 5124.0];

fn random_value(rng: &mut impl Rng) -> Value {
    match rng.random_range(0..9) {
        0 => Value::Null,
        1 => Value::Bool(rng.random()),
        2 => json!([]),
        3 => json!({}),
        4 => json!(STRINGS[rng.random_range(0..STRINGS.len())]),
        5 => json!(rng.random_range(-4..64)),
        6 => json!([0.0, 1e39, -1.0]),
        7 => json!(COMPONENT_TYPES[rng.random_range(0..COMPONENT_TYPES.len())] as u32),
        _ => number(rng),
    }
}

fn number(rng: &mut impl Rng) -> Value {
    let v = NUMBERS[rng.random_range(0..NUMBERS.len())];
    if v.fract() == 0.0 && (0.0..1.8e19).contains(&v) {
        json!(v as u64)
    } else if v.fract() == 0.0 && (-9.3e18..0.0).contains(&v) {
        json!(v as i64)
    } else {
        json!(v)
    }
}

/// Pointers (RFC 6901) to every value under `v`, at most `limit` of them, chosen evenly when
/// there are more (large scenes have tens of thousands).
fn pointers(v: &Value, rng: &mut impl Rng, limit: usize) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![(String::new(), v)];
    let mut seen = 0usize;
    while let Some((path, node)) = stack.pop() {
        seen += 1;
        // Reservoir sampling keeps a uniform sample of every pointer.
        if out.len() < limit {
            out.push(path.clone());
        } else {
            let j = rng.random_range(0..seen);
            if j < limit {
                out[j] = path.clone();
            }
        }
        match node {
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    stack.push((format!("{path}/{i}"), x));
                }
            }
            Value::Object(o) => {
                for (k, x) in o {
                    let k = k.replace('~', "~0").replace('/', "~1");
                    stack.push((format!("{path}/{k}"), x));
                }
            }
            _ => {}
        }
    }
    out
}

/// One structural change to the JSON document.
pub fn mutate_json(v: &mut Value, rng: &mut impl Rng) {
    let ptrs = pointers(v, rng, 4096);
    let ptr = &ptrs[rng.random_range(0..ptrs.len())];
    let Some(target) = v.pointer_mut(ptr) else {
        return;
    };
    match target {
        Value::Number(n) if (n.is_u64() || n.is_i64()) && rng.random_bool(0.8) => {
            // Integer fields (indices, counts, offsets, enums) mostly get integers, which
            // pass deserialization and reach the importer's own checks.
            let x = n.as_i64().unwrap_or(0);
            *target = match rng.random_range(0..4) {
                0 => json!(x + [-1i64, 1, 2, 3, 1000][rng.random_range(0..5)]),
                1 => json!(
                    [
                        0u64,
                        1,
                        3,
                        4,
                        255,
                        65535,
                        65536,
                        4294967295,
                        4294967296,
                        1 << 53,
                        u64::MAX
                    ][rng.random_range(0..11)]
                ),
                2 => json!(COMPONENT_TYPES[rng.random_range(0..COMPONENT_TYPES.len())] as u32),
                _ => json!(x.saturating_mul([2i64, 1000, -1][rng.random_range(0..3)])),
            }
        }
        Value::Number(n) => {
            *target = match rng.random_range(0..5) {
                0 => random_value(rng),
                1 => {
                    // Near the current value: off-by-one indices and counts.
                    let x = n.as_f64().unwrap_or(0.0);
                    json!(x + [-1.0, 1.0, 2.0, 1000.0][rng.random_range(0..4)])
                }
                2 => {
                    let x = n.as_f64().unwrap_or(1.0);
                    json!(x * [-1.0, 1e6, 1e30, 0.0][rng.random_range(0..4)])
                }
                _ => number(rng),
            }
        }
        Value::String(_) => {
            *target = if rng.random_bool(0.8) {
                json!(STRINGS[rng.random_range(0..STRINGS.len())])
            } else {
                random_value(rng)
            }
        }
        Value::Array(a) => match rng.random_range(0..4) {
            0 if !a.is_empty() => {
                let i = rng.random_range(0..a.len());
                a.remove(i);
            }
            1 if !a.is_empty() => {
                let i = rng.random_range(0..a.len());
                let x = a[i].clone();
                a.push(x);
            }
            2 => a.clear(),
            _ => a.push(random_value(rng)),
        },
        Value::Object(o) => match rng.random_range(0..3) {
            0 if !o.is_empty() => {
                let k = o.keys().nth(rng.random_range(0..o.len())).cloned();
                if let Some(k) = k {
                    o.remove(&k);
                }
            }
            _ => {
                let k = KEYS[rng.random_range(0..KEYS.len())];
                let value = match k {
                    "componentType" => {
                        json!(COMPONENT_TYPES[rng.random_range(0..COMPONENT_TYPES.len())] as u32)
                    }
                    "type" => json!(STRINGS[rng.random_range(22..28)]),
                    _ => random_value(rng),
                };
                o.insert(k.to_string(), value);
            }
        },
        _ => *target = random_value(rng),
    }
}

/// Interesting 32-bit patterns for binary payloads: float specials and integer extremes.
const WORDS: &[u32] = &[
    0x7fc0_0000, // NaN
    0xffc0_0001, // negative NaN with payload
    0x7f80_0000, // +inf
    0xff80_0000, // -inf
    0x7e96_7699, // 1e38
    0xfe96_7699, // -1e38
    0x8000_0000, // -0
    0x0000_0001, // smallest denormal
    0x7f7f_ffff, // f32::MAX
    0xffff_ffff,
    0x0000_ffff,
    0x8000_0001,
];

/// Byte-level changes to `bytes` (1 to 3 of them).
pub fn mutate_bytes(bytes: &mut Vec<u8>, rng: &mut impl Rng) {
    for _ in 0..rng.random_range(1..=3) {
        if bytes.is_empty() {
            bytes.push(rng.random());
            continue;
        }
        let i = rng.random_range(0..bytes.len());
        match rng.random_range(0..8) {
            0 => bytes[i] ^= 1 << rng.random_range(0..8),
            1 => bytes[i] = rng.random(),
            2 => bytes[i] = b"\"{}[],:0123456789-e.\\"[rng.random_range(0..21)],
            3 => {
                let end = (i + rng.random_range(1..64)).min(bytes.len());
                bytes.drain(i..end);
            }
            4 => {
                let end = (i + rng.random_range(1..64)).min(bytes.len());
                let chunk = bytes[i..end].to_vec();
                let at = rng.random_range(0..=bytes.len());
                bytes.splice(at..at, chunk);
            }
            5 if i + 4 <= bytes.len() => {
                let w = WORDS[rng.random_range(0..WORDS.len())];
                bytes[i..i + 4].copy_from_slice(&w.to_le_bytes());
            }
            6 => bytes.truncate(i),
            _ => {
                let n = rng.random_range(1..16);
                let fill: Vec<u8> = (0..n).map(|_| rng.random()).collect();
                bytes.splice(i..i, fill);
            }
        }
    }
}

/// Corrupts the decoded payload of one data-URI buffer or image in `v` (aligned float
/// specials, random bytes, truncation), if there is one.
pub fn mutate_payload(v: &mut Value, rng: &mut impl Rng) -> bool {
    let mut uris = Vec::new();
    for list in ["buffers", "images"] {
        if let Some(a) = v.get(list).and_then(Value::as_array) {
            for (i, item) in a.iter().enumerate() {
                if item
                    .get("uri")
                    .and_then(Value::as_str)
                    .is_some_and(|u| u.starts_with("data:") && u.contains(";base64,"))
                {
                    uris.push((list, i));
                }
            }
        }
    }
    if uris.is_empty() {
        return false;
    }
    let (list, i) = uris[rng.random_range(0..uris.len())];
    let uri = v[list][i]["uri"].as_str().unwrap_or_default().to_string();
    let (head, payload) = uri.split_once(";base64,").unwrap_or_default();
    let Ok(mut bytes) = base64::engine::general_purpose::STANDARD.decode(payload) else {
        return false;
    };
    if bytes.len() >= 4 && rng.random_bool(0.6) {
        // Aligned words: vertex data is floats and indices.
        for _ in 0..rng.random_range(1..=4) {
            let w = rng.random_range(0..bytes.len() / 4) * 4;
            let word = WORDS[rng.random_range(0..WORDS.len())];
            bytes[w..w + 4].copy_from_slice(&word.to_le_bytes());
        }
    } else {
        mutate_bytes(&mut bytes, rng);
    }
    let b64 = base64::engine::general_purpose::STANDARD.encode(&bytes);
    v[list][i]["uri"] = Value::String(format!("{head};base64,{b64}"));
    true
}

/// One mutated input from `seed` (a `.gltf`'s JSON or a GLB).
pub fn mutate(seed: &[u8], rng: &mut impl Rng) -> Vec<u8> {
    let rounds = rng.random_range(1..=3);
    let is_glb = seed.starts_with(b"glTF");
    // GLB: mutate the container's bytes, or its JSON chunk and repack.
    if is_glb {
        if rng.random_bool(0.3) {
            let mut b = seed.to_vec();
            mutate_bytes(&mut b, rng);
            return b;
        }
        let len = seed
            .get(12..16)
            .map(|l| u32::from_le_bytes([l[0], l[1], l[2], l[3]]) as usize)
            .unwrap_or(0);
        let (json, bin) = match (seed.get(20..20 + len), seed.get(20 + len + 8..)) {
            (Some(j), Some(b)) => (j, b),
            (Some(j), None) => (j, &[][..]),
            _ => return seed.to_vec(),
        };
        let Ok(mut v) = serde_json::from_slice::<Value>(json) else {
            return seed.to_vec();
        };
        for _ in 0..rounds {
            mutate_json(&mut v, rng);
        }
        let mut bin = bin.to_vec();
        if rng.random_bool(0.3) && bin.len() >= 4 {
            let w = rng.random_range(0..bin.len() / 4) * 4;
            bin[w..w + 4].copy_from_slice(&WORDS[rng.random_range(0..WORDS.len())].to_le_bytes());
        }
        return crate::seeds::glb(&serde_json::to_vec(&v).unwrap_or_default(), &bin);
    }
    // Mostly structural: byte noise mostly stops at the JSON parser.
    match rng.random_range(0..20) {
        0..=15 => {
            let Ok(mut v) = serde_json::from_slice::<Value>(seed) else {
                let mut b = seed.to_vec();
                mutate_bytes(&mut b, rng);
                return b;
            };
            for _ in 0..rounds {
                if rng.random_bool(0.25) {
                    mutate_payload(&mut v, rng);
                } else {
                    mutate_json(&mut v, rng);
                }
            }
            serde_json::to_vec(&v).unwrap_or_default()
        }
        16..=18 => {
            let mut b = seed.to_vec();
            mutate_bytes(&mut b, rng);
            b
        }
        _ => seed[..rng.random_range(0..seed.len().max(1))].to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn mutations_change_their_input_and_are_reproducible() {
        let seed = serde_json::to_vec(&json!({"asset": {"version": "2.0"},
            "buffers": [{"byteLength": 4, "uri": "data:application/octet-stream;base64,AAAAAA=="}],
            "accessors": [{"count": 3, "type": "VEC3"}]}))
        .unwrap();
        let mut changed = 0;
        for i in 0..200 {
            let a = mutate(&seed, &mut rand_pcg::Pcg64::seed_from_u64(i));
            let b = mutate(&seed, &mut rand_pcg::Pcg64::seed_from_u64(i));
            assert_eq!(a, b, "case {i} is not reproducible");
            changed += (a != seed) as usize;
        }
        assert!(changed > 190, "{changed} of 200 changed");
    }
}
