//! The byte format of a snapshot (module documentation of [`super`]): header, checksum and the
//! bincode payload, written and read; nothing about pipelines.

use super::{FORMAT_VERSION, HEADER_LEN, MAGIC, MAX_PAYLOAD, Snapshot, SnapshotError};

/// FNV-1a 64 of `bytes` (the payload checksum).
pub(super) fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3))
}

/// bincode 2 `standard()` with the payload limit.
fn codec() -> impl bincode::config::Config {
    bincode::config::standard().with_limit::<MAX_PAYLOAD>()
}

impl Snapshot {
    /// The bytes of the snapshot: header and payload (see the module documentation).
    pub fn encode(&self) -> Result<Vec<u8>, SnapshotError> {
        let payload = bincode::serde::encode_to_vec(self, codec()).map_err(|e| SnapshotError::Decode(e.to_string()))?;
        let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
        out.extend_from_slice(&MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        out.extend_from_slice(&fnv1a64(&payload).to_le_bytes());
        out.extend_from_slice(&payload);
        Ok(out)
    }

    /// Decodes and validates bytes made by [`Snapshot::encode`]; every failure is an error.
    pub fn decode(bytes: &[u8]) -> Result<Self, SnapshotError> {
        if bytes.len() < HEADER_LEN {
            if !MAGIC.starts_with(&bytes[..bytes.len().min(MAGIC.len())]) {
                return Err(SnapshotError::BadMagic);
            }
            return Err(SnapshotError::Truncated { have: bytes.len(), need: HEADER_LEN });
        }
        let word = |r: std::ops::Range<usize>| {
            let mut b = [0u8; 8];
            b[..r.len()].copy_from_slice(&bytes[r]);
            u64::from_le_bytes(b)
        };
        if bytes[..8] != MAGIC {
            return Err(SnapshotError::BadMagic);
        }
        let version = word(8..12) as u32;
        if version != FORMAT_VERSION {
            return Err(SnapshotError::Version { found: version });
        }
        let len = word(12..20);
        if len > MAX_PAYLOAD as u64 {
            return Err(SnapshotError::TooLarge(len));
        }
        let need = HEADER_LEN + len as usize;
        if bytes.len() != need {
            return Err(SnapshotError::Truncated { have: bytes.len(), need });
        }
        let payload = &bytes[HEADER_LEN..];
        if fnv1a64(payload) != word(20..28) {
            return Err(SnapshotError::Checksum);
        }
        let (snapshot, used): (Self, usize) =
            bincode::serde::decode_from_slice(payload, codec()).map_err(|e| SnapshotError::Decode(e.to_string()))?;
        if used != payload.len() {
            return Err(SnapshotError::Decode(format!("{} trailing bytes", payload.len() - used)));
        }
        snapshot.validate()?;
        Ok(snapshot)
    }
}
