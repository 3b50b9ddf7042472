//! rmf_api_msgs' JSON schemas from ../shared, for the RMF request and state tests.

use serde_json::Value;
use std::path::{Path, PathBuf};

/// ../shared/rmf_api_msgs: the schemas `$ref` each other by file name.
fn api_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/rmf_api_msgs")
}

/// Finds a referenced schema among the shared ones by its file name (never the network).
struct Local(PathBuf);

impl jsonschema::Retrieve for Local {
    fn retrieve(
        &self,
        uri: &jsonschema::Uri<String>,
    ) -> Result<Value, Box<dyn std::error::Error + Send + Sync>> {
        let name = uri
            .path()
            .as_str()
            .rsplit('/')
            .next()
            .unwrap_or("")
            .to_string();
        for sub in ["schemas", "task_descriptions"] {
            let p = self.0.join(sub).join(&name);
            if p.is_file() {
                return Ok(serde_json::from_str(&std::fs::read_to_string(p)?)?);
            }
        }
        Err(format!("no shared schema {uri}").into())
    }
}

/// The validator of schema `name` (in `schemas/` or `task_descriptions/`), or None when
/// ../shared is absent. A missing or broken schema fails the test.
pub fn validator(name: &str) -> Option<jsonschema::Validator> {
    let root = api_root();
    if !root.is_dir() {
        return None;
    }
    let path = ["schemas", "task_descriptions"]
        .iter()
        .map(|s| root.join(s).join(name))
        .find(|p| p.is_file())
        .unwrap_or_else(|| panic!("no schema {name} in {}", root.display()));
    let v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    Some(
        jsonschema::options()
            .with_retriever(Local(root))
            .build(&v)
            .expect("valid schema"),
    )
}
