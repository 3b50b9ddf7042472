//! Files a scenario names (a fleet's `config:`, `requests:`), read within the input limit,
//! their diagnostics under file ids after the scenario's.

use super::*;

impl P<'_> {
    /// Reads a file the scenario names (relative to the scenario's directory) and keeps
    /// it with the scenario's sources; returns its index in `included`.
    pub(super) fn include(&mut self, v: &Node, what: &str) -> Option<usize> {
        let name = self.name(v, what)?;
        let path = self.base.join(&name);
        self.include_path(path, v.span, what)
    }

    pub(super) fn include_path(&mut self, path: PathBuf, from: Span, what: &str) -> Option<usize> {
        let text = match read_limited(&path) {
            Ok(t) => t,
            Err(e) => {
                self.error(
                    codes::INCLUDED_FILE,
                    from,
                    format!("{what} `{}` cannot be read: {e}", path.display()),
                );
                self.help(if what == "`--requests`" {
                    "the path is relative to the current directory"
                } else {
                    "the path is relative to the scenario file"
                });
                return None;
            }
        };
        self.included.push(Included { path, text, from });
        Some(self.included.len() - 1)
    }

    /// `requests: FILE` or `{file: FILE, start_unix_millis: N}`: the requests, their
    /// `unix_millis_earliest_start_time` read against N (the run's start; default 0).
    /// With `--requests FILE` (`self.requests`), that file instead of the scenario's.
    pub(super) fn requests_file(
        &mut self,
        v: Option<&Node>,
        duration: Option<f64>,
    ) -> Option<Vec<RequestSpec>> {
        let (file, epoch) = match v {
            None => (None, 0),
            Some(v) => {
                let (f, e) = self.requests_key(v)?;
                (Some(f), e)
            }
        };
        let k = match (self.requests.clone(), file) {
            (Some(path), _) => {
                let from = file.map_or(Span::UNKNOWN, |f| f.span);
                self.include_path(path, from, "`--requests`")?
            }
            (None, Some(f)) => self.include(f, "`requests`")?,
            (None, None) => return Some(Vec::new()),
        };
        let id = self.included_id(k);
        let text = self.included[k].text.clone();
        let mut reqs = self.requests(id, &text)?;
        for r in &mut reqs {
            r.start_unix_millis = epoch;
            if let RequestKind::Task(t) = &r.what {
                if let Some(ms) = t.earliest_start_ms {
                    r.at = r.at.max(ms.saturating_sub(epoch) as f64 / 1000.0);
                }
            }
            if let Some(d) = duration.filter(|&d| r.at >= d) {
                self.warning(
                    codes::TASK_AFTER_END,
                    r.span,
                    format!(
                        "the request arrives (or may start) at {} s, at or after the end of the run ({d} s)",
                        r.at
                    ),
                );
                self.help("check `at` and `unix_millis_earliest_start_time` (read against `start_unix_millis`)");
            }
        }
        Some(reqs)
    }

    /// The `requests` key: its file node and `start_unix_millis`.
    pub(super) fn requests_key<'n, 'a>(&mut self, v: &'n Node<'a>) -> Option<(&'n Node<'a>, i64)> {
        let (file, epoch) = if v.as_map().is_some() {
            let e = self.entries(
                v,
                "`requests`",
                Some((&["file", "start_unix_millis"], codes::UNKNOWN_KEY)),
            )?;
            let f = self.required(&e, "file", "`requests`")?;
            let epoch = match e.get("start_unix_millis") {
                None => 0,
                Some(n) => self.int(n, "`start_unix_millis`")?,
            };
            (f, epoch)
        } else {
            (v, 0)
        };
        Some((file, epoch))
    }

    pub(super) fn included_id(&self, k: usize) -> FileId {
        FileId(self.file.0 + 1 + k as u32)
    }
}

/// Reads a file a scenario names, within the input limit, as UTF-8.
fn read_limited(path: &Path) -> Result<String, String> {
    use std::io::Read;
    let limit = mapc_frontend::MAX_FILE_BYTES;
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!(
            "it is larger than the input limit of {limit} bytes"
        ));
    }
    String::from_utf8(bytes).map_err(|_| "it is not valid UTF-8".to_string())
}
