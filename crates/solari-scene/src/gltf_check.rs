//! Checks made on a glTF document before the `gltf` crate reads it, because the crate (1.4.1)
//! asserts, indexes out of range or hits `unreachable!()` on some malformed input instead of
//! returning an error. Each check names the upstream site it guards (see the crate README's
//! "Known upstream issues").

use gltf::accessor::{DataType, Dimensions};
use gltf::json;

/// Extensions this importer reads; a file that *requires* any other is refused.
pub const SUPPORTED_EXTENSIONS: [&str; 4] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
];

/// Refuses a file that *requires* an extension this importer does not read, naming it.
pub fn check_required_extensions(root: &json::Root) -> Result<(), String> {
    for ext in &root.extensions_required {
        if !SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            return Err(format!(
                "the file requires extension {ext}, which this importer does not support \
                 (supported: {})",
                SUPPORTED_EXTENSIONS.join(", ")
            ));
        }
    }
    Ok(())
}

/// A primitive attribute naming an accessor that does not exist, as (mesh, primitive,
/// reason): checked before `Document::from_json` validates the file, because gltf-json
/// 1.4.1's primitive validation hook indexes `accessors[POSITION]` without a bounds check
/// (`mesh.rs:151`).
pub fn check_attribute_indices(root: &json::Root) -> Result<(), (usize, usize, String)> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= root.accessors.len() {
                    return Err((
                        m,
                        p,
                        format!(
                            "attribute {} names accessor {} but the file has {}",
                            semantic.to_string(),
                            index.value(),
                            root.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Checks an image's JSON before `gltf::Image::source()`, which unwraps (gltf 1.4.1
/// `image.rs:125,128`): an image needs a URI or a buffer view, and a buffer view needs a MIME
/// type.
pub fn check_image(image: &json::image::Image) -> Result<(), String> {
    match (&image.uri, &image.buffer_view, &image.mime_type) {
        (Some(_), None, _) => Ok(()),
        (None, Some(_), Some(_)) => Ok(()),
        (None, Some(_), None) => Err("has a buffer view but no mimeType".into()),
        (Some(_), Some(_), _) => Err("has both a uri and a buffer view".into()),
        (None, None, _) => Err("has neither a uri nor a buffer view".into()),
    }
}

/// The vertex attributes and index data this importer reads, with the layouts glTF 2.0
/// allows for each (the `gltf` crate's readers reach `unreachable!()` on others, e.g. BYTE
/// indices at `mesh/mod.rs:396` and UNSIGNED_INT texture coordinates at `mesh/mod.rs:430`, and
/// read a VEC2 POSITION as VEC3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Usage {
    /// `POSITION`: VEC3 float.
    Position,
    /// `NORMAL`: VEC3 float.
    Normal,
    /// `TANGENT`: VEC4 float.
    Tangent,
    /// `TEXCOORD_n`: VEC2 float, or normalized unsigned byte/short.
    TexCoord,
    /// Primitive indices: SCALAR unsigned byte/short/int, not normalized.
    Indices,
}

/// Whether an accessor's declared type suits `usage`.
pub fn check_layout(acc: &gltf::Accessor, usage: Usage) -> Result<(), String> {
    let (dt, dims, norm) = (acc.data_type(), acc.dimensions(), acc.normalized());
    let ok = match usage {
        Usage::Position | Usage::Normal => dims == Dimensions::Vec3 && dt == DataType::F32,
        Usage::Tangent => dims == Dimensions::Vec4 && dt == DataType::F32,
        Usage::TexCoord => {
            dims == Dimensions::Vec2
                && (dt == DataType::F32 || (norm && matches!(dt, DataType::U8 | DataType::U16)))
        }
        Usage::Indices => {
            dims == Dimensions::Scalar
                && !norm
                && matches!(dt, DataType::U8 | DataType::U16 | DataType::U32)
        }
    };
    if ok {
        Ok(())
    } else {
        let allowed = match usage {
            Usage::Position | Usage::Normal => "VEC3 FLOAT",
            Usage::Tangent => "VEC4 FLOAT",
            Usage::TexCoord => "VEC2 FLOAT, or VEC2 normalized UNSIGNED_BYTE/UNSIGNED_SHORT",
            Usage::Indices => "SCALAR UNSIGNED_BYTE/UNSIGNED_SHORT/UNSIGNED_INT",
        };
        Err(format!(
            "is {dims:?} {dt:?}{} but {usage:?} must be {allowed}",
            if norm { " normalized" } else { "" }
        ))
    }
}

/// Checks that an accessor's elements lie inside its buffer view and its view inside a buffer
/// of `buffer_len` bytes, and that the view's stride is legal (gltf 1.4.1 asserts on a stride
/// smaller than the element at `accessor/util.rs:253,266`).
pub fn check_extent(acc: &gltf::Accessor, buffer_len: usize) -> Result<(), String> {
    if acc.sparse().is_some() {
        return Err("sparse accessors are not supported".into());
    }
    let Some(view) = acc.view() else {
        return Err("has no buffer view".into());
    };
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|e| e > buffer_len) {
        return Err(format!(
            "buffer view {} (offset {}, length {}) reaches past its buffer of {buffer_len} bytes",
            view.index(),
            view.offset(),
            view.length(),
        ));
    }
    let elem = acc.size();
    if let Some(stride) = view.stride()
        && (stride < elem || stride > 252 || !stride.is_multiple_of(4))
    {
        return Err(format!(
            "buffer view {} has byteStride {stride}, but elements of {elem} bytes need a \
             stride of at least {elem}, at most 252 and a multiple of 4",
            view.index()
        ));
    }
    if acc.count() == 0 {
        return Ok(());
    }
    let stride = view.stride().unwrap_or(elem);
    let end = (acc.count() - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(acc.offset()))
        .and_then(|x| x.checked_add(elem));
    if end.is_none_or(|e| e > view.length()) {
        return Err(format!(
            "{} elements of {elem} bytes (stride {stride}) at offset {} do not fit buffer view \
             {} of {} bytes",
            acc.count(),
            acc.offset(),
            view.index(),
            view.length()
        ));
    }
    Ok(())
}
