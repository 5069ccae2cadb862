//! Reading `.rrd` recordings back (tests, and anyone checking what a run wrote).

use std::io::BufReader;
use std::path::Path;

use re_log_encoding::DecoderApp;
use rerun::log::{Chunk, LogMsg};
use rerun::StoreKind;

/// Readback errors, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum ReadbackError {
    #[error("{path}: cannot open recording: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: cannot decode recording: {message}")]
    Decode { path: String, message: String },
}

/// Every log message of the file at `path`, in file order.
fn read_messages(path: &Path) -> Result<Vec<LogMsg>, ReadbackError> {
    let file = std::fs::File::open(path).map_err(|source| ReadbackError::Io {
        path: path.display().to_string(),
        source,
    })?;
    DecoderApp::decode_lazy(BufReader::new(file))
        .collect::<Result<Vec<LogMsg>, _>>()
        .map_err(|e| ReadbackError::Decode {
            path: path.display().to_string(),
            message: e.to_string(),
        })
}

/// All data chunks of the recording store (blueprint chunks excluded), in file order.
pub fn recording_chunks(path: &Path) -> Result<Vec<Chunk>, ReadbackError> {
    message_chunks(&read_messages(path)?, &path.display().to_string())
}

/// The entity paths of the recording's layout (its blueprint store: `view/ID`, `view/ID/TimeAxis`,
/// `container/ID`, …), in file order, each once.
pub fn layout_entities(path: &Path) -> Result<Vec<String>, ReadbackError> {
    let chunks = store_chunks(
        &read_messages(path)?,
        &path.display().to_string(),
        StoreKind::Blueprint,
    )?;
    let mut out: Vec<String> = Vec::new();
    for chunk in chunks {
        let e = chunk.entity_path().to_string();
        if !out.contains(&e) {
            out.push(e);
        }
    }
    Ok(out)
}

/// The data chunks of the recording store among log messages (e.g. of a memory sink); `origin`
/// names them in errors.
pub fn message_chunks(msgs: &[LogMsg], origin: &str) -> Result<Vec<Chunk>, ReadbackError> {
    store_chunks(msgs, origin, StoreKind::Recording)
}

/// The data chunks of the stores of `kind` among log messages.
fn store_chunks(msgs: &[LogMsg], origin: &str, kind: StoreKind) -> Result<Vec<Chunk>, ReadbackError> {
    let mut chunks = Vec::new();
    for msg in msgs {
        if let LogMsg::ArrowMsg(store, arrow) = msg {
            if store.kind() != kind {
                continue;
            }
            let chunk = Chunk::from_arrow_msg(arrow).map_err(|e| ReadbackError::Decode {
                path: origin.to_string(),
                message: e.to_string(),
            })?;
            chunks.push(chunk);
        }
    }
    Ok(chunks)
}

/// Every scalar of the entity `entity` (e.g. `/run/wheelset_1/y_mm`) among `chunks`, row by row
/// in chunk order (each row the entity's values at one time), static chunks excluded.
pub fn scalar_rows(chunks: &[Chunk], entity: &str) -> Vec<Vec<f64>> {
    chunks
        .iter()
        .filter(|c| c.entity_path().to_string() == entity && !c.is_static())
        .flat_map(|c| {
            c.iter_slices::<f64>(rerun::Scalars::descriptor_scalars().component)
                .map(|v| v.to_vec())
                .collect::<Vec<_>>()
        })
        .collect()
}
