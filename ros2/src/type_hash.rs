//! ROS 2 type hashes (REP-2011, `RIHS01_<sha256>`), computed from mapc's `.msg` definitions
//! as rosidl computes them: the type's description (`type_description_interfaces`: each
//! field's name, type id, capacities and nested type name; constants and default values
//! left out) and those of every type it references, sorted by name, as JSON with Python's
//! `", "` and `": "` separators, hashed with SHA-256. rmw_zenoh_cpp puts the hash in every
//! topic's key expression and liveliness token, so a subscriber matches only a publisher
//! of the same definition.

use crate::msgs;
use sha2::{Digest, Sha256};
use std::collections::BTreeSet;

/// One field's `type_description_interfaces/FieldType`.
struct FieldType {
    type_id: u32,
    capacity: u64,
    string_capacity: u64,
    nested_type_name: String,
}

/// `FieldType.msg`'s id of a basic type (`None` for a nested type).
fn basic_type_id(t: &str) -> Option<u32> {
    Some(match t {
        "int8" => 2,
        // `char` is rosidl's alias of uint8.
        "uint8" | "char" => 3,
        "int16" => 4,
        "uint16" => 5,
        "int32" => 6,
        "uint32" => 7,
        "int64" => 8,
        "uint64" => 9,
        "float32" => 10,
        "float64" => 11,
        "bool" => 15,
        "byte" => 16,
        "string" => 17,
        "wstring" => 18,
        _ => return None,
    })
}

/// Parses a `.msg` field type (`float64`, `string<=10`, `pkg/Name[]`, `uint8[3]`, ...).
fn field_type(t: &str) -> Result<FieldType, String> {
    let (base, array) = match t.find('[') {
        Some(i) => (&t[..i], Some(t[i + 1..].trim_end_matches(']'))),
        None => (t, None),
    };
    let (base, string_capacity) = match base.split_once("<=") {
        Some((b, n)) => (b, n.parse().map_err(|_| format!("bad bound in `{t}`"))?),
        None => (base, 0),
    };
    let (mut type_id, nested_type_name) = match basic_type_id(base) {
        // Bounded strings have ids of their own.
        Some(17) if string_capacity > 0 => (21, String::new()),
        Some(18) if string_capacity > 0 => (22, String::new()),
        Some(id) => (id, String::new()),
        None => {
            let (pkg, name) = base
                .split_once('/')
                .ok_or_else(|| format!("type `{base}` is not fully qualified"))?;
            (1, format!("{pkg}/msg/{name}"))
        }
    };
    let mut capacity = 0;
    match array {
        None => {}
        Some("") => type_id += 144,
        Some(n) => match n.strip_prefix("<=") {
            Some(n) => {
                type_id += 96;
                capacity = n.parse().map_err(|_| format!("bad bound in `{t}`"))?;
            }
            None => {
                type_id += 48;
                capacity = n.parse().map_err(|_| format!("bad size in `{t}`"))?;
            }
        },
    }
    Ok(FieldType {
        type_id,
        capacity,
        string_capacity,
        nested_type_name,
    })
}

/// The fields of a `.msg` text: (name, type); constants (`TYPE NAME=value`) are not fields.
fn fields(def: &str) -> Result<Vec<(String, FieldType)>, String> {
    let mut out = Vec::new();
    for line in def.lines() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let mut words = line.split_whitespace();
        let (Some(t), Some(name)) = (words.next(), words.next()) else {
            return Err(format!("cannot read `{line}`"));
        };
        if name.contains('=') || words.clone().next().is_some_and(|w| w.starts_with('=')) {
            continue;
        }
        out.push((name.to_string(), field_type(t)?));
    }
    if out.is_empty() {
        // rosidl gives an empty structure one member (C cannot have empty structs).
        out.push((
            "structure_needs_at_least_one_member".into(),
            field_type("uint8")?,
        ));
    }
    Ok(out)
}

/// One `IndividualTypeDescription` as rosidl's JSON (without default values).
fn individual_json(name: &str, fields: &[(String, FieldType)]) -> String {
    let fields: Vec<String> = fields
        .iter()
        .map(|(n, t)| {
            format!(
                "{{\"name\": {}, \"type\": {{\"type_id\": {}, \"capacity\": {}, \
                 \"string_capacity\": {}, \"nested_type_name\": {}}}}}",
                json_str(n),
                t.type_id,
                t.capacity,
                t.string_capacity,
                json_str(&t.nested_type_name)
            )
        })
        .collect();
    format!(
        "{{\"type_name\": {}, \"fields\": [{}]}}",
        json_str(name),
        fields.join(", ")
    )
}

/// A JSON string as Python's `json.dumps(ensure_ascii=True)` writes it.
fn json_str(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 || (c as u32) > 0x7e => {
                let mut buf = [0u16; 2];
                for u in c.encode_utf16(&mut buf) {
                    out.push_str(&format!("\\u{u:04x}"));
                }
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The JSON rosidl hashes for `name` (`package/msg/Name`), from mapc's definitions.
pub fn hashable_json(name: &str) -> Result<String, String> {
    let def = |n: &str| msgs::definition(n).ok_or_else(|| format!("no definition of {n}"));
    let top = fields(def(name)?)?;
    let mut referenced = BTreeSet::new();
    let mut queue: Vec<String> = top
        .iter()
        .map(|(_, t)| t.nested_type_name.clone())
        .filter(|n| !n.is_empty())
        .collect();
    while let Some(n) = queue.pop() {
        if referenced.insert(n.clone()) {
            for (_, t) in fields(def(&n)?)? {
                if !t.nested_type_name.is_empty() {
                    queue.push(t.nested_type_name);
                }
            }
        }
    }
    let refs: Vec<String> = referenced
        .iter()
        .map(|n| Ok(individual_json(n, &fields(def(n)?)?)))
        .collect::<Result<_, String>>()?;
    Ok(format!(
        "{{\"type_description\": {}, \"referenced_type_descriptions\": [{}]}}",
        individual_json(name, &top),
        refs.join(", ")
    ))
}

/// `RIHS01_<64 hex digits>` of `name` (`package/msg/Name`).
pub fn type_hash(name: &str) -> Result<String, String> {
    let digest = Sha256::digest(hashable_json(name)?.as_bytes());
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    Ok(format!("RIHS01_{hex}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hashes that ROS 2 (Jazzy) published for the same definitions: rosidl_generator_c's
    /// `*__description.c` (`*__get_type_hash`, 32 bytes after the version 1) of
    /// builtin_interfaces, std_msgs, geometry_msgs and rosgraph_msgs (ros2/rcl_interfaces,
    /// ros2/common_interfaces) and of rmf_door_msgs (open-rmf/rmf_internal_msgs) as found
    /// in public colcon build trees; std_msgs/String's is also the example of
    /// rmw_zenoh_cpp's design document (`0/chatter/std_msgs::msg::dds_::String_/RIHS01_df66…`).
    const PUBLISHED: &[(&str, &str)] = &[
        (
            "builtin_interfaces/msg/Time",
            "b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197",
        ),
        (
            "std_msgs/msg/String",
            "df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18",
        ),
        (
            "geometry_msgs/msg/Point",
            "6963084842a9b04494d6b2941d11444708d892da2f4b09843b9c43f42a7f6881",
        ),
        (
            "geometry_msgs/msg/Quaternion",
            "8a765f66778c8ff7c8ab94afcc590a2ed5325a1d9a076ffff38fbce36f458684",
        ),
        (
            "rosgraph_msgs/msg/Clock",
            "692f7a66e93a3c83e71765d033b60349ba68023a8c689a79e48078bcb5c58564",
        ),
        (
            "rmf_door_msgs/msg/DoorMode",
            "02c834bb83aa3ca1fbd8cf4f61a1d1ae4dc8227111bde3820dda580f8c2c6429",
        ),
        (
            "rmf_door_msgs/msg/DoorState",
            "1cb9d98f19c66cbc1f9acb16faaa90c63a7b65021bd26c69958d96f0a0388bb2",
        ),
        (
            "rmf_door_msgs/msg/DoorRequest",
            "3145b5d97064f89b0a0db953b8167ddeeefbc2914c24a603c3bdc51f122f143e",
        ),
    ];

    #[test]
    fn hashes_equal_those_ros2_published() {
        for (name, hex) in PUBLISHED {
            assert_eq!(
                type_hash(name).unwrap(),
                format!("RIHS01_{hex}"),
                "{name}: {}",
                hashable_json(name).unwrap()
            );
        }
    }

    #[test]
    fn every_definition_hashes() {
        for (name, _) in msgs::definitions() {
            let h = type_hash(name).unwrap();
            assert_eq!(h.len(), 71, "{name}");
        }
    }

    #[test]
    fn field_types_as_rosidl() {
        let t = field_type("string<=10").unwrap();
        assert_eq!((t.type_id, t.string_capacity), (21, 10));
        let t = field_type("float64[36]").unwrap();
        assert_eq!((t.type_id, t.capacity), (59, 36));
        let t = field_type("pkg/Name[<=3]").unwrap();
        assert_eq!((t.type_id, t.capacity), (97, 3));
        assert_eq!(t.nested_type_name, "pkg/msg/Name");
        assert_eq!(field_type("uint8[]").unwrap().type_id, 147);
        assert_eq!(json_str("a\"é"), "\"a\\\"\\u00e9\"");
    }
}
