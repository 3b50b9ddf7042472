//! CDR (XCDR1, little endian) as ROS 2 puts it on the wire and in rosbag2: a 4-byte
//! encapsulation header `00 01 00 00` (CDR_LE), then the fields, each aligned to its size
//! relative to the end of the header. Generic over serde: the bytes follow from the types
//! (`crate::msgs`), with no conversion per message.

use byteorder::LittleEndian;
use serde::{de::DeserializeOwned, Serialize};

/// The CDR_LE encapsulation header.
pub const HEADER: [u8; 4] = [0, 1, 0, 0];

/// The message's CDR payload (without the header), as DDS writers send it after theirs.
pub fn body<T: Serialize>(msg: &T) -> Vec<u8> {
    // Serialising plain structs of numbers, strings and sequences into a Vec cannot fail.
    cdr_encoding::to_vec::<T, LittleEndian>(msg).unwrap_or_default()
}

/// Header and payload, as rosbag2 stores a message.
pub fn encode<T: Serialize>(msg: &T) -> Vec<u8> {
    let mut out = HEADER.to_vec();
    out.extend(body(msg));
    out
}

/// Reads a serialised message (header included; big-endian CDR is accepted too).
pub fn decode<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, String> {
    if bytes.len() < 4 {
        return Err("shorter than the CDR header".into());
    }
    let body = &bytes[4..];
    match bytes[..2] {
        [0, 1] => from_body::<T, LittleEndian>(body),
        [0, 0] => from_body::<T, byteorder::BigEndian>(body),
        _ => Err(format!(
            "unsupported encapsulation {:02x}{:02x}",
            bytes[0], bytes[1]
        )),
    }
}

pub(crate) fn from_body<T: DeserializeOwned, B: byteorder::ByteOrder>(
    body: &[u8],
) -> Result<T, String> {
    cdr_encoding::from_bytes::<T, B>(body)
        .map(|(v, _)| v)
        .map_err(|e| e.to_string())
}
