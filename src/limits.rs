//! Size limits that an input meets before any structure is built, kept below every layer that
//! enforces them (the loaders in `scene`, the hierarchies in `accel`), so neither imports the
//! other for them.

/// Most triangles (or instance boxes) one hierarchy holds: a leaf's first item must fit the
/// 28 bits its child reference gives it. The OBJ loader and the scene format keep within it.
pub const MAX_HIERARCHY_ITEMS: usize = (1 << 28) - 1;

/// The longest image side in pixels (a render, a view, a scene camera's focal length must suit
/// every size up to it).
pub const MAX_IMAGE_SIDE: u32 = 16_384;

/// The deepest `push` nesting a `.scene` file may have. Every open level holds its matrix,
/// inverse and inspector node (about 500 bytes for a 5-byte line): without a bound, 10⁶ nested
/// `push` lines took 653 MB. Scenes built with the transform stack nest a few levels.
pub const MAX_PUSH_DEPTH: usize = 1000;
