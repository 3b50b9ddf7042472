//! Diagnostic codes the backends report while producing output (W07xx). Each `///` block is
//! gathered into docs/diagnostics.md (see tests/docs.rs), like frontend/src/codes.rs.

use mapc_ir::lints::Group;
pub use mapc_ir::Code;

/// # W0701 texture-not-found
///
/// **What:** a wall, floor or ceiling names a texture, and no `<name>.png` exists in any
/// directory of the texture search path (`--texture-path DIR` options in order, then the
/// colon-separated `MAPC_TEXTURE_PATH`, then the map file's directory), or the file found
/// is not a readable PNG image, or the name is not a plain file name.
///
/// **Why it matters:** the reference generator crashes on a missing texture. mapc writes
/// its output anyway, with a generated magenta-and-grey checkerboard in place of the
/// texture, so the surface is easy to spot in a viewer.
///
/// **Fix:** pass the directory holding the textures with `--texture-path` (traffic_editor's
/// textures are in its `building_map_tools/building_map/textures/`), or correct the name.
///
/// **Example:**
/// ```yaml
/// walls:
///   - [0, 1, {texture_name: [1, no_such_texture]}]
/// ```
pub const TEXTURE_NOT_FOUND: Code = Code {
    code: "W0701",
    group: Group::Textures,
    name: "texture-not-found",
    summary: "a texture could not be found on the texture search path",
};

/// # W0702 texture-url-not-fetched
///
/// **What:** a texture name is an `http://` or `https://` URL. The reference generator
/// downloads such textures; mapc never goes to the network while compiling.
///
/// **Why it matters:** the surface gets the generated placeholder texture instead of the
/// image at the URL.
///
/// **Fix:** download the image, put it in a directory of the texture search path, and name
/// it by its file name without `.png`.
///
/// **Example:**
/// ```yaml
/// floors:
///   - parameters: {texture_name: [1, "https://example.com/tiles.png"]}
/// ```
pub const TEXTURE_URL: Code = Code {
    code: "W0702",
    group: Group::Textures,
    name: "texture-url-not-fetched",
    summary: "a texture named by URL is not downloaded; a placeholder is used",
};

/// Every backend code, in code order.
pub static CODES: &[Code] = &[TEXTURE_NOT_FOUND, TEXTURE_URL];
