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

/// The most mesh placements (instances) one `.scene` file may make by default. Each costs
/// about 800 bytes (its matrices and boxes, its share of the hierarchy over placements) for a
/// 14-byte `mesh` line: without a bound, 10⁷ placements passed 6 GB; at this one they stay under
/// 1 GB. A field of a thousand bunnies makes a thousand.
pub const MAX_PLACEMENTS: u64 = 1 << 20;

/// The most triangles that copies of meshes a `.scene` file uses repeatedly (`mesh` lines of
/// one file, `cornell` lines) may be flattened to. A small mesh is flattened by choice (its
/// rays walk faster so) while all its copies fit the file's room, [`flattened_copies_room`],
/// else placed as instances; copies that only flattening can hold (a matrix too
/// ill-conditioned to place one) are refused past this limit, whatever the file's size (their
/// memory grows with the mesh file, which is input too). Each
/// flattened triangle costs about 110 bytes: without a bound, 550,000 `cornell` lines (4.4 MB)
/// took 3.3 GB; at this one the copies stay near 120 MB.
pub const MAX_FLATTENED_COPIES: u64 = 1 << 20;

/// The room for flattened copies every scene file has, however short: 2¹⁵ triangles (about
/// 3.6 MB), enough to flatten a thousand Cornell boxes.
pub const FLATTENED_COPIES_FLOOR: u64 = 1 << 15;

/// The room for flattened copies of a scene file of `bytes`: [`FLATTENED_COPIES_FLOOR`] and
/// one triangle for every 2 bytes of the file (about 55 bytes a byte), at most
/// [`MAX_FLATTENED_COPIES`]. Past it copies are placed (where their matrix allows), so
/// memory stays in proportion to the file: the whole room for 280 KB of `cornell` lines took
/// 120 MB flattened, 25 MB placed.
pub fn flattened_copies_room(bytes: usize) -> u64 {
    (FLATTENED_COPIES_FLOOR + bytes as u64 / 2).min(MAX_FLATTENED_COPIES)
}

/// The placement limit in force: [`MAX_PLACEMENTS`] unless `RAYLAB_MAX_PLACEMENTS` says (at
/// most what a hierarchy holds, [`MAX_HIERARCHY_ITEMS`]).
pub fn max_placements() -> u64 {
    crate::input::limit_from_env("RAYLAB_MAX_PLACEMENTS", MAX_PLACEMENTS)
        .min(MAX_HIERARCHY_ITEMS as u64)
}

/// The most entries (push levels and the statements written in them) the scene tree of a
/// `.scene` file records for the panel by default. Each costs about 200 bytes for a few bytes of
/// input (`push` and `pop` lines): without a bound, 5·10⁶ sequential push/pop pairs (45 MB)
/// took a gigabyte. Beyond it the file renders the same; the tree lists the first entries and
/// a warning says where it stopped.
pub const MAX_TREE_ENTRIES: u64 = 1 << 20;

/// The scene-tree limit in force: [`MAX_TREE_ENTRIES`] unless `RAYLAB_MAX_TREE_ENTRIES` says.
pub fn max_tree_entries() -> u64 {
    crate::input::limit_from_env("RAYLAB_MAX_TREE_ENTRIES", MAX_TREE_ENTRIES)
}

/// The longest line of a `.scene` or `.view` file, in bytes. A statement takes a few hundred
/// bytes; without a bound a 300 MB line was split into words (2.9 GB) before its error.
pub const MAX_LINE_BYTES: usize = 1 << 20;
