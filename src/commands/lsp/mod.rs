//! `mapc lsp`: a language server on stdin/stdout for `.building.yaml`, legacy
//! `.project.yaml` and `.scenario.yaml` files.
//!
//! One thread does everything, in batches: it takes every message already waiting, applies
//! all text changes, re-checks each changed document once (so a burst of keystrokes costs
//! one check of the last text: stale work is dropped, not done), publishes diagnostics,
//! then answers the batch's requests against the new text (those cancelled meanwhile get
//! `RequestCancelled`). Checking a clinic-size map takes about 3 ms, so nothing waits long.

mod actions;
mod analysis;
mod diagnostics;
mod document;
mod hover;
mod navigation;
mod outline;
mod params_doc;
mod symbols;

use crate::driver::lints::Lints;
use crate::driver::{CliError, Outcome};
use analysis::Analysis;
use document::{Document, Kind};
use lsp_server::{Connection, ErrorCode, Message, Notification, Request, RequestId, Response};
use lsp_types::notification::{self as note, Notification as _};
use lsp_types::request::{self as req, Request as _};
use lsp_types::{
    CodeActionProviderCapability, HoverProviderCapability, OneOf, PublishDiagnosticsParams,
    ServerCapabilities, ServerInfo, TextDocumentSyncCapability, TextDocumentSyncKind,
    TextDocumentSyncOptions, TextDocumentSyncSaveOptions, Uri,
};
use std::collections::{BTreeMap, HashSet};
use std::path::Path;

#[derive(clap::Args)]
pub(crate) struct LspArgs {
    /// Accepted and ignored: stdio is the only transport (some clients always pass it).
    #[arg(long)]
    stdio: bool,
    #[command(flatten)]
    lints: crate::driver::LintOpts,
}

/// An open document with its latest check.
struct Open {
    uri: Uri,
    doc: Document,
    lints: Result<Lints, String>,
    analysis: Option<Analysis>,
    dirty: bool,
}

struct Server<'a> {
    args: &'a LspArgs,
    docs: BTreeMap<String, Open>,
    shutdown: bool,
}

pub(crate) fn run(args: &LspArgs) -> Result<Outcome, CliError> {
    // Bad lint flags are a usage error now, not a diagnostic in every file later.
    crate::driver::lints::from_flags(
        &args.lints.allow,
        &args.lints.warn,
        &args.lints.deny,
        args.lints.deny_warnings,
    )?;
    let (conn, io) = Connection::stdio();
    let caps = ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Options(
            TextDocumentSyncOptions {
                open_close: Some(true),
                change: Some(TextDocumentSyncKind::INCREMENTAL),
                save: Some(TextDocumentSyncSaveOptions::Supported(true)),
                ..TextDocumentSyncOptions::default()
            },
        )),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        workspace_symbol_provider: Some(OneOf::Left(true)),
        code_action_provider: Some(CodeActionProviderCapability::Simple(true)),
        ..ServerCapabilities::default()
    };
    let init = serde_json::json!({
        "capabilities": caps,
        "serverInfo": ServerInfo { name: "mapc".into(), version: Some(env!("CARGO_PKG_VERSION").into()) },
    });
    let started = conn
        .initialize_start()
        .and_then(|(id, _)| conn.initialize_finish(id, init));
    if let Err(e) = started {
        return Err(CliError::Usage(format!("mapc lsp: {e}")));
    }
    let mut server = Server {
        args,
        docs: BTreeMap::new(),
        shutdown: false,
    };
    let clean = server.main_loop(&conn);
    drop(conn);
    let _ = io.join();
    if clean {
        Ok(Outcome::Done)
    } else {
        // The LSP's exit code for an `exit` that came without `shutdown`.
        Err(CliError::InvalidReported)
    }
}

impl Server<'_> {
    /// Runs until `exit`; true when it came after `shutdown` (the protocol's clean end).
    fn main_loop(&mut self, conn: &Connection) -> bool {
        while let Ok(first) = conn.receiver.recv() {
            let mut batch = vec![first];
            batch.extend(conn.receiver.try_iter());
            let mut requests = Vec::new();
            let mut cancelled: HashSet<RequestId> = HashSet::new();
            for msg in batch {
                match msg {
                    Message::Request(r) => requests.push(r),
                    Message::Notification(n) => {
                        if n.method == note::Exit::METHOD {
                            return self.shutdown;
                        }
                        if n.method == note::Cancel::METHOD {
                            if let Ok(p) =
                                serde_json::from_value::<lsp_types::CancelParams>(n.params)
                            {
                                cancelled.insert(match p.id {
                                    lsp_types::NumberOrString::Number(i) => RequestId::from(i),
                                    lsp_types::NumberOrString::String(s) => RequestId::from(s),
                                });
                            }
                            continue;
                        }
                        self.notification(conn, n);
                    }
                    Message::Response(_) => {}
                }
            }
            self.flush(conn);
            for r in requests {
                let resp = if cancelled.contains(&r.id) {
                    Response::new_err(r.id, ErrorCode::RequestCanceled as i32, "cancelled".into())
                } else if self.shutdown {
                    Response::new_err(
                        r.id,
                        ErrorCode::InvalidRequest as i32,
                        "shutting down".into(),
                    )
                } else {
                    self.request(r)
                };
                let _ = conn.sender.send(resp.into());
            }
        }
        false
    }

    fn lints_for(&self, doc: &Document) -> Result<Lints, String> {
        let path = doc
            .path
            .clone()
            .unwrap_or_else(|| Path::new("untitled").to_path_buf());
        crate::driver::lints_for(&path, &self.args.lints)
    }

    fn notification(&mut self, conn: &Connection, n: Notification) {
        match n.method.as_str() {
            note::DidOpenTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidOpenTextDocumentParams>(n.params)
                else {
                    return;
                };
                let td = p.text_document;
                let Some(kind) = Kind::of(td.uri.as_str()) else {
                    return;
                };
                let doc = Document::new(td.uri.as_str().to_string(), kind, td.version, td.text);
                let lints = self.lints_for(&doc);
                self.docs.insert(
                    td.uri.as_str().to_string(),
                    Open {
                        uri: td.uri,
                        doc,
                        lints,
                        analysis: None,
                        dirty: true,
                    },
                );
            }
            note::DidChangeTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidChangeTextDocumentParams>(n.params)
                else {
                    return;
                };
                if let Some(o) = self.docs.get_mut(p.text_document.uri.as_str()) {
                    o.doc.apply(p.text_document.version, p.content_changes);
                    o.dirty = true;
                }
            }
            note::DidSaveTextDocument::METHOD => {
                // mapc.toml may have changed meanwhile; a saved project's building too.
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidSaveTextDocumentParams>(n.params)
                else {
                    return;
                };
                let key = p.text_document.uri.as_str().to_string();
                if let Some(o) = self.docs.get(&key) {
                    let lints = self.lints_for(&o.doc);
                    let o = self.docs.get_mut(&key).expect("just found");
                    o.lints = lints;
                    o.dirty = true;
                }
            }
            note::DidCloseTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidCloseTextDocumentParams>(n.params)
                else {
                    return;
                };
                if self.docs.remove(p.text_document.uri.as_str()).is_some() {
                    publish(conn, p.text_document.uri, Vec::new(), None);
                }
            }
            _ => {}
        }
    }

    /// Re-checks every changed document once and publishes its diagnostics.
    fn flush(&mut self, conn: &Connection) {
        for o in self.docs.values_mut().filter(|o| o.dirty) {
            o.dirty = false;
            let default = Lints::default();
            let lints = o.lints.as_ref().unwrap_or(&default);
            let analysis = analysis::check(&o.doc, lints);
            let mut diags: Vec<lsp_types::Diagnostic> = analysis
                .diagnostics
                .iter()
                .map(|d| diagnostics::to_lsp(&o.doc, &o.uri, d))
                .collect();
            if let Err(e) = &o.lints {
                // A broken mapc.toml: said at the top of the file, default levels used.
                diags.push(lsp_types::Diagnostic {
                    severity: Some(lsp_types::DiagnosticSeverity::ERROR),
                    source: Some("mapc".into()),
                    message: format!("{e} (default lint levels used)"),
                    ..lsp_types::Diagnostic::default()
                });
            }
            diags.sort_by_key(|d| (d.range.start, d.range.end));
            publish(conn, o.uri.clone(), diags, Some(o.doc.version));
            o.analysis = Some(analysis);
        }
    }

    fn request(&mut self, r: Request) -> Response {
        let id = r.id.clone();
        if r.method == req::Shutdown::METHOD {
            self.shutdown = true;
            return Response::new_ok(id, ());
        }
        match self.answer(r) {
            Ok(v) => Response {
                id,
                response_result: Ok(v),
            },
            Err((code, msg)) => Response::new_err(id, code as i32, msg),
        }
    }

    fn open(&self, uri: &Uri) -> Result<&Open, (ErrorCode, String)> {
        self.docs.get(uri.as_str()).ok_or((
            ErrorCode::InvalidParams,
            format!("{} is not open", uri.as_str()),
        ))
    }

    fn answer(&self, r: Request) -> Result<serde_json::Value, (ErrorCode, String)> {
        fn params<P: serde::de::DeserializeOwned>(
            v: serde_json::Value,
        ) -> Result<P, (ErrorCode, String)> {
            serde_json::from_value(v).map_err(|e| (ErrorCode::InvalidParams, e.to_string()))
        }
        let json = |v: serde_json::Value| Ok(v);
        match r.method.as_str() {
            req::HoverRequest::METHOD => {
                let p: lsp_types::HoverParams = params(r.params)?;
                let o = self.open(&p.text_document_position_params.text_document.uri)?;
                json(
                    serde_json::to_value(hover::hover(
                        &o.doc,
                        o.analysis.as_ref(),
                        p.text_document_position_params.position,
                    ))
                    .unwrap_or_default(),
                )
            }
            req::GotoDefinition::METHOD => {
                let p: lsp_types::GotoDefinitionParams = params(r.params)?;
                let tdp = p.text_document_position_params;
                let o = self.open(&tdp.text_document.uri)?;
                json(
                    serde_json::to_value(navigation::definition(&o.doc, &o.uri, tdp.position))
                        .unwrap_or_default(),
                )
            }
            req::References::METHOD => {
                let p: lsp_types::ReferenceParams = params(r.params)?;
                let tdp = p.text_document_position;
                let o = self.open(&tdp.text_document.uri)?;
                let locs = navigation::references(
                    &o.doc,
                    &o.uri,
                    tdp.position,
                    p.context.include_declaration,
                );
                json(serde_json::to_value(locs).unwrap_or_default())
            }
            req::DocumentSymbolRequest::METHOD => {
                let p: lsp_types::DocumentSymbolParams = params(r.params)?;
                let o = self.open(&p.text_document.uri)?;
                json(
                    serde_json::to_value(symbols::document_symbols(&o.doc, o.analysis.as_ref()))
                        .unwrap_or_default(),
                )
            }
            req::WorkspaceSymbolRequest::METHOD => {
                let p: lsp_types::WorkspaceSymbolParams = params(r.params)?;
                let docs = self
                    .docs
                    .values()
                    .map(|o| (&o.uri, &o.doc, o.analysis.as_ref()));
                json(
                    serde_json::to_value(symbols::workspace_symbols(docs, &p.query))
                        .unwrap_or_default(),
                )
            }
            req::CodeActionRequest::METHOD => {
                let p: lsp_types::CodeActionParams = params(r.params)?;
                let o = self.open(&p.text_document.uri)?;
                let actions = match &o.analysis {
                    Some(a) => actions::code_actions(&o.doc, &o.uri, a, p.range),
                    None => Vec::new(),
                };
                json(serde_json::to_value(actions).unwrap_or_default())
            }
            m => Err((
                ErrorCode::MethodNotFound,
                format!("mapc lsp does not handle {m}"),
            )),
        }
    }
}

fn publish(
    conn: &Connection,
    uri: Uri,
    diagnostics: Vec<lsp_types::Diagnostic>,
    version: Option<i32>,
) {
    let params = PublishDiagnosticsParams {
        uri,
        diagnostics,
        version,
    };
    let n = Notification::new(note::PublishDiagnostics::METHOD.to_string(), params);
    let _ = conn.sender.send(n.into());
}

/// `text` as a YAML scalar: plain when a YAML 1.1 or 1.2 reader would read it back as that
/// string, double-quoted otherwise.
pub(crate) fn yaml_scalar(text: &str) -> String {
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
        && text.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        && !matches!(
            text.to_ascii_lowercase().as_str(),
            "true" | "false" | "yes" | "no" | "on" | "off" | "y" | "n" | "null" | "nan" | "inf"
        );
    if plain {
        text.to_string()
    } else {
        serde_json::to_string(text).unwrap_or_default()
    }
}
