//! The serialized FMU state: magic `RWYFMUST`, format version, model identifier, GUID, the
//! shell's part (call state, times, flags), the model's bytes ([`FmuModel::save_state`]) and an
//! FNV-1a checksum. `fmi2FMUstate` handles point to a heap copy of these bytes.

use crate::codec::{fnv1a64, ByteReader, ByteWriter};
use crate::instance::{CallState, Instance};
use crate::model::FmuModel;

pub(crate) const FMU_STATE_MAGIC: u64 = 0x5241_4345_5741_5953; // "RACEWAYS"

/// Magic bytes and version of the serialized FMU state.
pub const STATE_MAGIC: &[u8; 8] = b"RWYFMUST";
/// Version of the format written by this shell.
// 2: the call state as a u32 (the Model Exchange states are bits 8 and 9).
pub const STATE_FORMAT_VERSION: u32 = 2;

/// A saved FMU state (what `fmi2FMUstate` points to): the serialized bytes.
pub(crate) struct SavedState {
    pub(crate) magic: u64,
    pub(crate) bytes: Vec<u8>,
}

impl<M: FmuModel> Instance<M> {
    /// The full serialized FMU state (header + shell + model + checksum).
    pub(crate) fn serialize(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.raw(STATE_MAGIC)
            .u32(STATE_FORMAT_VERSION)
            .str(M::MODEL_IDENTIFIER)
            .str(self.model.guid())
            .u32(self.state as u32)
            .f64(self.time)
            .f64(self.start_time)
            .opt_f64(self.stop_time)
            .opt_f64(self.tolerance)
            .f64(self.last_successful_time)
            .bool(self.terminated)
            .bytes(&self.model.save_state());
        let sum = fnv1a64(&w.buf);
        w.u64(sum);
        w.into_bytes()
    }

    /// Checks a serialized state without applying it.
    pub(crate) fn check_blob<'a>(&self, bytes: &'a [u8]) -> Result<ShellSnapshot<'a>, String> {
        if bytes.len() < STATE_MAGIC.len() + 4 + 8 || &bytes[..8] != STATE_MAGIC {
            return Err(format!(
                "not a serialized {} FMU state (bad magic or {} bytes only)",
                M::MODEL_IDENTIFIER,
                bytes.len()
            ));
        }
        let version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
        if version != STATE_FORMAT_VERSION {
            return Err(format!(
                "state format version {version} is not supported (this FMU reads version {STATE_FORMAT_VERSION})"
            ));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        if fnv1a64(body) != u64::from_le_bytes(sum.try_into().expect("8 bytes")) {
            return Err(format!(
                "truncated or corrupt FMU state ({} bytes, checksum mismatch)",
                bytes.len()
            ));
        }
        let mut r = ByteReader::new(&body[12..]);
        let ident = r.str("model identifier")?;
        if ident != M::MODEL_IDENTIFIER {
            return Err(format!(
                "the state belongs to FMU '{ident}', not '{}'",
                M::MODEL_IDENTIFIER
            ));
        }
        let guid = r.str("GUID")?;
        if guid != self.model.guid() {
            return Err(format!(
                "the state was saved by an FMU with GUID {guid}; this instance is {}",
                self.model.guid()
            ));
        }
        let state_code = r.u32("call state")?;
        let state = u16::try_from(state_code)
            .ok()
            .and_then(CallState::from_u16)
            .filter(|s| *s != CallState::Fatal)
            .ok_or_else(|| format!("corrupt state: call state {state_code}"))?;
        if !state.belongs_to(self.interface) {
            return Err(format!(
                "the state was saved by a {} instance (call state {state:?}); this instance is \
                 {}",
                self.interface.other().name(),
                self.interface.name()
            ));
        }
        let snap = ShellSnapshot {
            state,
            time: r.f64("time")?,
            start_time: r.f64("start time")?,
            stop_time: r.opt_f64("stop time")?,
            tolerance: r.opt_f64("tolerance")?,
            last_successful_time: r.f64("last successful time")?,
            terminated: r.bool("terminated flag")?,
            model: r.bytes("model state")?,
        };
        r.finish("the model state")?;
        Ok(snap)
    }
}

/// A checked serialized state, not yet applied.
pub(crate) struct ShellSnapshot<'a> {
    pub(crate) state: CallState,
    pub(crate) time: f64,
    pub(crate) start_time: f64,
    pub(crate) stop_time: Option<f64>,
    pub(crate) tolerance: Option<f64>,
    pub(crate) last_successful_time: f64,
    pub(crate) terminated: bool,
    pub(crate) model: &'a [u8],
}
