//! The recording's file sink: the SDK's log messages encoded into an `.rrd` file by kecsim, so
//! that every write's error is seen. (The SDK's own `FileSink` writes on a thread that stops at
//! its first failed write, logs it and returns nothing: a full disk left a truncated recording
//! "saved" over the previous one, and a flush queued behind the failed write waited forever.)
//!
//! The messages are encoded as the SDK's file sink encodes them (protobuf, LZ4-compressed, a
//! footer with the chunk manifest at the end) and written to an open file — the part file of
//! [`crate::files`], or a stream (`/dev/stdout`, a named pipe) written directly. The first
//! error is kept and reported by every flush after it (`RecordingStream::flush_blocking`); the
//! footer is written when the stream's last handle drops, and the caller checks the file's end
//! ([`super::finish_recording`]).

use std::io::Write;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use re_log_encoding::{CrateVersion, Encoder, EncodingOptions};
use rerun::log::LogMsg;
use rerun::sink::{LogSink, SinkFlushError};

type Enc = Encoder<std::io::BufWriter<std::fs::File>>;

#[derive(Default)]
struct State {
    encoder: Option<Enc>,
    error: Option<String>,
}

/// The sink handed to the recording stream.
struct Sink(Arc<Mutex<State>>);

/// The file of a sink handed to a stream that also goes elsewhere (a viewer, with `--connect`
/// and `--save` together): its end is written by [`Handle::finish`] when the run ends, whatever
/// the other sink's end waits for.
#[derive(Clone)]
pub struct Handle(Arc<Mutex<State>>);

impl std::fmt::Debug for Handle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("rrd_file::Handle")
    }
}

impl Handle {
    /// Writes the file's footer and its last bytes (once; later messages are not written);
    /// the first error of any write, if one failed.
    pub fn finish(&self) -> Result<(), String> {
        let mut s = lock(&self.0);
        if let Some(e) = s.encoder.take() {
            if let Err(e) = finish_encoder(e) {
                s.error.get_or_insert(e);
            }
        }
        s.error.clone().map_or(Ok(()), Err)
    }
}

fn finish_encoder(mut e: Enc) -> Result<(), String> {
    e.finish().map_err(|e| e.to_string())?;
    let mut w = e.into_inner().map_err(|e| e.to_string())?;
    w.flush().map_err(|e| e.to_string())
}

fn lock(s: &Mutex<State>) -> std::sync::MutexGuard<'_, State> {
    s.lock().unwrap_or_else(|e| e.into_inner())
}

impl LogSink for Sink {
    fn send(&self, msg: LogMsg) {
        let mut s = lock(&self.0);
        if s.error.is_some() {
            return;
        }
        let failed = s.encoder.as_mut().map(|e| e.append(&msg).err());
        if let Some(Some(e)) = failed {
            s.error = Some(e.to_string());
            // Nothing more is written: the file is abandoned.
            s.encoder = None;
        }
    }

    fn flush_blocking(&self, _timeout: Duration) -> Result<(), SinkFlushError> {
        let mut s = lock(&self.0);
        if let Some(e) = &s.error {
            return Err(SinkFlushError::failed(e.clone()));
        }
        let flushed = s.encoder.as_mut().map(|e| e.flush_blocking());
        if let Some(Err(e)) = flushed {
            let e = e.to_string();
            s.error = Some(e.clone());
            s.encoder = None;
            return Err(SinkFlushError::failed(e));
        }
        Ok(())
    }

    fn defers_finalization_to_shutdown(&self) -> bool {
        true
    }
}

/// A recording stream that writes into `file` (see the module doc).
pub fn stream_into(app_id: &'static str, file: std::fs::File) -> Result<rerun::RecordingStream, String> {
    let (sink, _) = sink_into(file)?;
    let rec = rerun::RecordingStreamBuilder::new(app_id)
        .buffered()
        .map_err(|e| e.to_string())?;
    rec.set_sink(sink);
    Ok(rec)
}

/// The sink that writes into `file`, and its handle (to end the file explicitly).
pub fn sink_into(file: std::fs::File) -> Result<(Box<dyn LogSink>, Handle), String> {
    let encoder = Encoder::new_eager(
        CrateVersion::LOCAL,
        EncodingOptions::PROTOBUF_COMPRESSED,
        std::io::BufWriter::new(file),
    )
    .map_err(|e| e.to_string())?;
    let state = Arc::new(Mutex::new(State {
        encoder: Some(encoder),
        error: None,
    }));
    Ok((Box::new(Sink(state.clone())), Handle(state)))
}

impl Drop for Sink {
    /// The footer and the last bytes (errors here show in the file's end, which the caller
    /// checks).
    fn drop(&mut self) {
        let mut s = lock(&self.0);
        if let Some(e) = s.encoder.take() {
            finish_encoder(e).ok();
        }
    }
}
