//! Textures for mesh outputs: which file a texture name stands for, the images found for
//! them, and the placeholder used when one cannot be found. Finding files is the caller's
//! job (backends do no I/O): [`resolve_textures`] takes a lookup function, and mapc's CLI
//! passes one that searches `--texture-path` directories, `MAPC_TEXTURE_PATH` and the map's
//! directory.

use crate::codes;
use crate::Mesh;
use mapc_ir::{Building, Diagnostic, Span};
use std::collections::{BTreeMap, BTreeSet};

/// An image to embed for a texture name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TextureImage {
    /// PNG file contents as read (the glTF writer embeds them without ancillary chunks).
    pub png: Vec<u8>,
    /// True when the texture was not found and `png` is [`placeholder_png`].
    pub placeholder: bool,
}

/// Texture name → image, for every name the meshes use.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Textures {
    pub images: BTreeMap<String, TextureImage>,
}

impl Textures {
    pub fn get(&self, name: &str) -> Option<&TextureImage> {
        self.images.get(name)
    }
}

/// Is the texture name an `http(s)://` URL (the reference downloads those)?
pub fn is_url(name: &str) -> bool {
    let lower = name.get(..8).unwrap_or(name).to_ascii_lowercase();
    lower.starts_with("http://") || lower.starts_with("https://")
}

/// The file name a plain texture name stands for (`<name>.png`), or `None` when the name
/// is a URL, empty, or not a single plain path component (so a name can never make mapc
/// read outside the search directories).
pub fn texture_file_name(name: &str) -> Option<String> {
    let plain = !name.is_empty()
        && !is_url(name)
        && name != "."
        && name != ".."
        && !name.contains(['/', '\\', '\0', ':']);
    plain.then(|| format!("{name}.png"))
}

/// Is `bytes` a PNG whose header the `png` crate can read?
pub fn is_png(bytes: &[u8]) -> bool {
    png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .is_ok()
}

/// Can more bytes of the file that begins with `head` not change what [`is_png`] says of
/// it? True once `head` reaches the first image-data chunk (the decoder reads no further to
/// accept a PNG), and when it cannot be a PNG's beginning at all (wrong signature, a chunk
/// length PNG forbids, or the end chunk first). A cheap walk over the chunk headers: the
/// decoder itself runs once, on the head this accepts ([`is_png`]).
pub fn png_head_is_enough(head: &[u8]) -> bool {
    const SIGNATURE: &[u8; 8] = b"\x89PNG\r\n\x1a\n";
    if head.len() < SIGNATURE.len() {
        return !SIGNATURE.starts_with(head);
    }
    if !head.starts_with(SIGNATURE) {
        return true;
    }
    let mut i = SIGNATURE.len();
    // Each chunk: length (4 bytes, at most 2^31 - 1), type (4), data, CRC (4).
    while let Some(header) = head.get(i..i + 8) {
        let len = u32::from_be_bytes([header[0], header[1], header[2], header[3]]);
        if len > i32::MAX as u32 {
            return true;
        }
        if matches!(&header[4..], b"IDAT" | b"fdAT" | b"IEND") {
            return true;
        }
        i = i.saturating_add(12).saturating_add(len as usize);
    }
    false
}

/// The PNG with only the chunks that define its pixels (IHDR, PLTE, tRNS, IDAT, IEND);
/// colour-space, text, time and other ancillary chunks are dropped. glTF 2.0 requires
/// viewers to ignore PNG colour-space information (§3.8.4.3), and the Khronos validator
/// warns about it, so the embedded image keeps exactly what is displayed. Chunks are copied
/// whole (CRCs unchanged); input that does not parse as a chunk sequence is returned as is.
pub fn strip_png(bytes: &[u8]) -> Vec<u8> {
    const SIGNATURE: &[u8; 8] = b"\x89PNG\r\n\x1a\n";
    const KEEP: [&[u8; 4]; 5] = [b"IHDR", b"PLTE", b"tRNS", b"IDAT", b"IEND"];
    if !bytes.starts_with(SIGNATURE) {
        return bytes.to_vec();
    }
    let mut out = SIGNATURE.to_vec();
    let mut i = SIGNATURE.len();
    while i < bytes.len() {
        let Some(len) = bytes
            .get(i..i + 4)
            .map(|b| u32::from_be_bytes(b.try_into().unwrap()) as usize)
        else {
            return bytes.to_vec();
        };
        let Some(chunk) = bytes.get(i..i.saturating_add(12).saturating_add(len)) else {
            return bytes.to_vec();
        };
        if KEEP.iter().any(|k| &chunk[4..8] == *k) {
            out.extend_from_slice(chunk);
        }
        i += chunk.len();
    }
    out
}

/// A generated 8×8 RGB checkerboard (magenta and grey, 2×2-pixel squares), used in place of
/// a texture that cannot be found. Always the same bytes.
pub fn placeholder_png() -> Vec<u8> {
    const N: u32 = 8;
    let mut pixels = Vec::with_capacity((N * N * 3) as usize);
    for y in 0..N {
        for x in 0..N {
            let on = ((x / 2) + (y / 2)) % 2 == 0;
            pixels.extend_from_slice(if on { &[255, 0, 255] } else { &[96, 96, 96] });
        }
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, N, N);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().expect("writing to a Vec cannot fail");
        w.write_image_data(&pixels)
            .expect("the pixel buffer matches the header");
    }
    out
}

/// Every texture name the meshes' materials use (base colour and PBR maps), sorted.
pub fn texture_names<'a>(meshes: impl IntoIterator<Item = &'a Mesh>) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    for m in meshes {
        if !m.material.texture.is_empty() {
            names.insert(m.material.texture.clone());
        }
        for (_, t) in &m.material.pbr_maps {
            if !t.is_empty() {
                names.insert(t.clone());
            }
        }
    }
    names
}

/// Where a texture name is written in the map: the first wall or floor parameter whose
/// string value is `name`, else the whole document.
fn texture_span(b: &Building, name: &str) -> Span {
    let params = b
        .walls
        .iter()
        .map(|(_, w)| &w.params)
        .chain(b.floors.iter().map(|(_, f)| &f.params));
    for ps in params {
        for p in ps.iter() {
            if p.value.as_str() == Some(name) {
                return p.span;
            }
        }
    }
    b.spans.root
}

/// Resolves every name: `find(file_name)` returns the contents of the first `<name>.png` on
/// the search path. A URL, a name that is not a plain file name, a file not found or not a
/// PNG gets the placeholder and a warning (W0701, W0702); this never fails.
pub fn resolve_textures<'a>(
    b: &Building,
    names: impl IntoIterator<Item = &'a str>,
    find: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
) -> (Textures, Vec<Diagnostic>) {
    let mut textures = Textures::default();
    let mut diags = Vec::new();
    // Encoded only when some texture needs it (most maps find all of theirs).
    let placeholder_image = std::cell::OnceCell::new();
    let placeholder = || -> TextureImage {
        placeholder_image
            .get_or_init(|| TextureImage {
                png: placeholder_png(),
                placeholder: true,
            })
            .clone()
    };
    for name in names {
        if textures.images.contains_key(name) {
            continue;
        }
        let span = texture_span(b, name);
        let image = if is_url(name) {
            diags.push(
                Diagnostic::warning(
                    codes::TEXTURE_URL.code,
                    span,
                    format!("texture `{name}` is a URL; mapc does not download textures"),
                )
                .with_help("download it into a --texture-path directory and name it by file name; a placeholder is used"),
            );
            placeholder()
        } else {
            let found = texture_file_name(name).and_then(|f| find(&f).map(|bytes| (f, bytes)));
            match found {
                // Kept as read: level models copy (or link) the file as it is; the glTF
                // embedding strips it.
                Some((_, png)) if is_png(&png) => TextureImage {
                    png,
                    placeholder: false,
                },
                Some((file, _)) => {
                    diags.push(
                        Diagnostic::warning(
                            codes::TEXTURE_NOT_FOUND.code,
                            span,
                            format!("texture file `{file}` is not a readable PNG image"),
                        )
                        .with_help("a placeholder texture is used instead"),
                    );
                    placeholder()
                }
                None => {
                    diags.push(
                        Diagnostic::warning(
                            codes::TEXTURE_NOT_FOUND.code,
                            span,
                            format!("texture `{name}` not found on the texture search path"),
                        )
                        .with_help(
                            "add its directory with --texture-path DIR or MAPC_TEXTURE_PATH; \
                             a placeholder texture is used instead",
                        ),
                    );
                    placeholder()
                }
            }
        };
        textures.images.insert(name.to_string(), image);
    }
    (textures, diags)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placeholder_is_a_valid_stable_png() {
        let a = placeholder_png();
        assert!(is_png(&a));
        assert_eq!(a, placeholder_png());
    }

    /// The placeholder with a tEXt chunk after IHDR (8 + 25 bytes), its CRC right.
    fn with_text_chunk() -> Vec<u8> {
        let mut png = placeholder_png();
        let mut text = Vec::new();
        text.extend_from_slice(&4u32.to_be_bytes());
        text.extend_from_slice(b"tEXtabcd");
        text.extend_from_slice(&png_crc(b"tEXtabcd").to_be_bytes());
        png.splice(33..33, text);
        png
    }

    #[test]
    fn strip_keeps_pixels_and_drops_metadata() {
        let png = with_text_chunk();
        let stripped = strip_png(&png);
        assert_eq!(stripped, placeholder_png());
        assert_eq!(strip_png(b"garbage"), b"garbage");
        let mut cut = placeholder_png();
        cut.truncate(40);
        assert_eq!(strip_png(&cut), cut);
    }

    /// Whenever the head is said to be enough, the decoder says of it what it says of the
    /// whole file: for every prefix of a PNG with an ancillary chunk before its pixels, of a
    /// damaged one and of one without a signature.
    #[test]
    fn a_head_said_to_be_enough_decides_as_the_whole_file() {
        let with_text = with_text_chunk();
        assert!(is_png(&with_text));
        let mut bad_crc = with_text.clone();
        bad_crc[30] ^= 1; // IHDR's CRC
        assert!(!is_png(&bad_crc));
        let mut no_signature = placeholder_png();
        no_signature[1] = b'X';
        let idat = with_text.windows(4).position(|w| w == b"IDAT").unwrap() - 4;
        for whole in [&placeholder_png(), &with_text, &bad_crc, &no_signature] {
            for n in 0..=whole.len() {
                let head = &whole[..n];
                if png_head_is_enough(head) {
                    assert_eq!(is_png(head), is_png(whole), "prefix of {n} bytes");
                }
            }
            assert!(png_head_is_enough(whole));
        }
        // Enough exactly from the image-data chunk's header on.
        assert!(!png_head_is_enough(&with_text[..idat + 7]));
        assert!(png_head_is_enough(&with_text[..idat + 8]));
        assert!(png_head_is_enough(b"GIF89a"));
        assert!(!png_head_is_enough(b"\x89PN"));
    }

    /// CRC-32 of PNG chunks (ISO 3309), for building test chunks.
    fn png_crc(bytes: &[u8]) -> u32 {
        let mut c = !0u32;
        for &b in bytes {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    0xEDB8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }

    #[test]
    fn file_names() {
        assert_eq!(texture_file_name("wall").as_deref(), Some("wall.png"));
        assert_eq!(texture_file_name("https://x.org/a.png"), None);
        assert_eq!(texture_file_name("HTTP://x.org/a.png"), None);
        assert_eq!(texture_file_name("../etc/passwd"), None);
        assert_eq!(texture_file_name(".."), None);
        assert_eq!(texture_file_name(""), None);
        assert!(is_url("https://example.com/t.png"));
        assert!(!is_url("httpish"));
    }

    #[test]
    fn missing_and_url_textures_get_placeholders_and_warnings() {
        let b = Building::new(
            "b".into(),
            mapc_ir::CoordinateSystem::CartesianMeters,
            Default::default(),
        );
        let good = placeholder_png();
        let mut find = |f: &str| match f {
            "ok.png" => Some(good.clone()),
            "bad.png" => Some(b"not a png".to_vec()),
            _ => None,
        };
        let (t, d) = resolve_textures(
            &b,
            ["ok", "bad", "gone", "https://e.org/x.png", "ok"],
            &mut find,
        );
        assert_eq!(t.images.len(), 4);
        assert!(!t.get("ok").unwrap().placeholder);
        assert!(t.get("bad").unwrap().placeholder);
        assert!(t.get("gone").unwrap().placeholder);
        assert!(t.get("https://e.org/x.png").unwrap().placeholder);
        let codes: Vec<_> = d.iter().map(|d| d.code).collect();
        assert_eq!(codes, ["W0701", "W0701", "W0702"]);
        assert!(d.iter().all(|d| !d.is_error()));
    }
}
