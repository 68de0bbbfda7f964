//! Typed errors for scene import and GPU setup.

use std::path::PathBuf;

/// Everything that can go wrong while importing a scene.
///
/// Every variant names the file and, where there is one, the glTF element at fault, so a user
/// can find the problem without a debugger.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file is not a regular file, is over the import size limit, or could not be read.
    #[error("{file}: cannot read: {reason}")]
    Unreadable {
        /// The file.
        file: PathBuf,
        /// Why (a directory, a device, over the limit, an OS error).
        reason: String,
    },
    /// The file needs something this importer does not do (a required extension).
    #[error("{file}: unsupported: {reason}")]
    Unsupported {
        /// The glTF file.
        file: PathBuf,
        /// What is needed.
        reason: String,
    },
    /// The imported scene breaks a rule rendering relies on ([`crate::Scene::validate`]):
    /// coordinates beyond f32's useful range, an unusable camera.
    #[error("{file}: {reason}")]
    Invalid {
        /// The glTF file.
        file: PathBuf,
        /// The rule broken, naming the element.
        reason: String,
    },
    /// A material's values are unusable (NaN or negative emission).
    #[error("{file}: material {material}: {reason}")]
    BadMaterial {
        /// The glTF file.
        file: PathBuf,
        /// The material's index in the glTF document.
        material: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// The `gltf` crate panicked on input that no check of ours caught: a bug to report (the
    /// import is abandoned, the program goes on).
    #[error(
        "{file}: the glTF reader failed on this file (an importer bug; please report it): {message}"
    )]
    ImporterPanic {
        /// The glTF file.
        file: PathBuf,
        /// The panic's message.
        message: String,
    },
    /// An environment map file is missing, unreadable, corrupt, not HDR or too large.
    #[error("{file}: environment map: {reason}")]
    Environment {
        /// The image file.
        file: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// The glTF JSON or GLB container is malformed.
    #[error("{file}: not a valid glTF file: {source}")]
    Gltf {
        /// The glTF file.
        file: PathBuf,
        /// The parser's error.
        source: gltf::Error,
    },
    /// A buffer's data is missing (a file that does not exist or lies outside the asset's
    /// folder, or no GLB blob).
    #[error("{file}: buffer {index}: data missing: {reason}")]
    MissingBuffer {
        /// The glTF file.
        file: PathBuf,
        /// The buffer's index in the glTF document.
        index: usize,
        /// What was missing.
        reason: String,
    },
    /// A buffer holds fewer bytes than the document declares.
    #[error("{file}: buffer {index}: holds {actual} bytes but declares {declared}")]
    TruncatedBuffer {
        /// The glTF file.
        file: PathBuf,
        /// The buffer's index in the glTF document.
        index: usize,
        /// Bytes the document declares.
        declared: usize,
        /// Bytes actually present.
        actual: usize,
    },
    /// An accessor or buffer view reaches outside its buffer, or has an unusable layout.
    #[error("{file}: accessor {accessor}: {reason}")]
    BadAccessor {
        /// The glTF file.
        file: PathBuf,
        /// The accessor's index in the glTF document.
        accessor: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A mesh primitive cannot be used (missing positions, out-of-range indices, non-finite data,
    /// unsupported topology).
    #[error("{file}: mesh {mesh} primitive {primitive}: {reason}")]
    BadPrimitive {
        /// The glTF file.
        file: PathBuf,
        /// The mesh's index in the glTF document.
        mesh: usize,
        /// The primitive's index inside the mesh.
        primitive: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A texture's image is missing or cannot be decoded.
    #[error("{file}: image {image}: {reason}")]
    BadImage {
        /// The glTF file.
        file: PathBuf,
        /// The image's index in the glTF document.
        image: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A node transform is not finite or the node graph is not a forest.
    #[error("{file}: node {node}: {reason}")]
    BadNode {
        /// The glTF file.
        file: PathBuf,
        /// The node's index in the glTF document.
        node: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// The scene has no triangle left to render.
    #[error("{file}: the scene is empty: {reason}")]
    EmptyScene {
        /// The glTF file (or `<built-in>`).
        file: PathBuf,
        /// Why nothing is left.
        reason: String,
    },
    /// The requested camera does not exist.
    #[error("{file}: no camera {wanted} (the scene has {available})")]
    NoSuchCamera {
        /// The glTF file.
        file: PathBuf,
        /// The name or index asked for.
        wanted: String,
        /// A list of the cameras that do exist.
        available: String,
    },
    /// A side file (such as `render_setup.json`) is malformed.
    #[error("{file}: {reason}")]
    BadSideFile {
        /// The side file.
        file: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
}

/// Errors of GPU setup and GPU resource creation.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter matched the request.
    #[error(
        "no GPU adapter found ({0}); install a Vulkan driver (on a machine without a GPU: `.ci/install-lavapipe`)"
    )]
    NoAdapter(String),
    /// `SOLARI_ADAPTER` asked for an adapter that does not exist.
    #[error("{0}")]
    AdapterRequest(String),
    /// The adapter lacks a feature the caller needs.
    #[error("adapter '{adapter}' lacks required features {missing:?}")]
    MissingFeatures {
        /// The adapter's name.
        adapter: String,
        /// The missing features.
        missing: wgpu::Features,
    },
    /// Device creation failed.
    #[error("cannot create a device on '{adapter}': {source}")]
    RequestDevice {
        /// The adapter's name.
        adapter: String,
        /// wgpu's error.
        source: wgpu::RequestDeviceError,
    },
    /// A resource is larger than the device allows.
    #[error("{what} needs {needed} bytes but the device allows at most {limit}")]
    OverLimit {
        /// Which resource.
        what: String,
        /// Bytes needed.
        needed: u64,
        /// The device limit.
        limit: u64,
    },
    /// The ray-query backend was asked for on an adapter without ray queries.
    #[error(
        "the ray-query tracer needs EXPERIMENTAL_RAY_QUERY, which adapter '{0}' does not offer; use the software tracer"
    )]
    NoRayQuery(String),
    /// The adapter cannot run a pass the caller asked for; the message says which and what
    /// to use instead.
    #[error("{0}")]
    Unsupported(String),
    /// WESL composition or naga validation of a shader failed.
    #[error("shader '{name}' failed to compile: {message}")]
    Shader {
        /// The entry-point file.
        name: String,
        /// The compiler's message.
        message: String,
    },
    /// The scene breaks a rule rendering relies on ([`crate::Scene::validate`]).
    #[error("the scene cannot be rendered: {0}")]
    BadScene(String),
    /// The non-finite detector found NaN, infinite or negative values in a frame
    /// ([`crate::finite_check`]); `pass` is the first pass, in frame order, that had any.
    #[error(
        "frame {frame}: pass {pass} produced {non_finite} non-finite and {negative} negative value(s)"
    )]
    NonFinite {
        /// The frame index.
        frame: u32,
        /// The first pass with a finding.
        pass: String,
        /// NaN or infinite values in that pass's output.
        non_finite: u64,
        /// Negative values where only non-negative ones are valid.
        negative: u64,
    },
    /// A request the library refuses before it reaches wgpu: a setting out of range, sizes
    /// that do not match, an input a pass cannot use. The message names the knob or input.
    #[error("{0}")]
    Validation(String),
    /// wgpu itself reported a validation error (captured by an error scope, or raised
    /// outside one and collected by `Gpu::check_errors`): a bug on this side, never bad
    /// input that the library let through on purpose.
    #[error("wgpu validation error: {0}")]
    Wgpu(String),
    /// Mapping a buffer for readback failed.
    #[error("buffer readback failed: {0}")]
    Readback(String),
}
