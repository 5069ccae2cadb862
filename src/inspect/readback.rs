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

/// All data chunks of the recording store (blueprint chunks excluded), in file order.
pub fn recording_chunks(path: &Path) -> Result<Vec<Chunk>, ReadbackError> {
    let p = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|source| ReadbackError::Io {
        path: p.clone(),
        source,
    })?;
    let mut chunks = Vec::new();
    for msg in DecoderApp::decode_lazy(BufReader::new(file)) {
        let msg = msg.map_err(|e| ReadbackError::Decode {
            path: p.clone(),
            message: e.to_string(),
        })?;
        if let LogMsg::ArrowMsg(store, arrow) = msg {
            if store.kind() != StoreKind::Recording {
                continue;
            }
            let chunk = Chunk::from_arrow_msg(&arrow).map_err(|e| ReadbackError::Decode {
                path: p.clone(),
                message: e.to_string(),
            })?;
            chunks.push(chunk);
        }
    }
    Ok(chunks)
}
