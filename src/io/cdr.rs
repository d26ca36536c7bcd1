//! A reader of CDR-encoded messages, the serialization ROS 2 uses on the wire and in its bags:
//! OMG CORBA 3.3 Part 2 §9.3 "CDR Transfer Syntax" as profiled by OMG DDS-XTypes 1.3 §7.4.3.4
//! ("XCDR1", encapsulation `CDR_BE` 0x0000 / `CDR_LE` 0x0001).
//!
//! A message starts with a 4-byte encapsulation header: a big-endian u16 encapsulation
//! identifier (its low bit: 1 = little endian) and a u16 of options. Every primitive of size s
//! sits at an offset that is a multiple of s counted from the end of that header (8-byte
//! primitives align to 8 in XCDR1). A string is a u32 length that counts a terminating NUL,
//! then its bytes and the NUL. Fixed-size arrays have no length prefix. The XCDR2 encapsulations
//! (identifiers 0x0006 and up), where 8-byte primitives align to 4, are refused with
//! [`CdrErrorKind::Encapsulation`] rather than read wrong.

use std::fmt;

/// Length of the encapsulation header, bytes.
pub const ENCAPSULATION_LEN: usize = 4;

/// What is wrong with a CDR buffer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CdrErrorKind {
    /// The buffer ends before the field does.
    Truncated {
        /// Bytes the field needs from its (aligned) offset.
        needed: usize,
        /// Bytes left in the buffer there.
        left: usize,
    },
    /// The encapsulation identifier is not XCDR1 (`CDR_BE`/`CDR_LE`).
    Encapsulation(u16),
    /// A string has length 0 (no room for its NUL), does not end in NUL, or is not UTF-8.
    BadString(String),
    /// A value outside its type's documented range (the message says which).
    OutOfRange(String),
    /// Bytes left after the message's last field, beyond the padding to a 4-byte multiple.
    TrailingBytes(usize),
}

impl fmt::Display for CdrErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Truncated { needed, left } => {
                write!(f, "message ends early: the field needs {needed} byte(s), {left} left")
            }
            Self::Encapsulation(id) => write!(
                f,
                "encapsulation 0x{id:04x} is not XCDR1 (0x0000 CDR_BE or 0x0001 CDR_LE; XCDR2 is not supported)"
            ),
            Self::BadString(msg) => write!(f, "bad string: {msg}"),
            Self::OutOfRange(msg) => f.write_str(msg),
            Self::TrailingBytes(n) => write!(f, "{n} byte(s) after the last field"),
        }
    }
}

/// A CDR problem: the field being read, its byte offset in the message and what went wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CdrError {
    /// Dotted path of the field (`header.stamp.nanosec`), or `encapsulation`.
    pub field: &'static str,
    /// Byte offset in the message (encapsulation header included) where the field starts.
    pub offset: usize,
    /// What went wrong.
    pub kind: CdrErrorKind,
}

impl fmt::Display for CdrError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "field `{}` (byte {}): {}", self.field, self.offset, self.kind)
    }
}

impl std::error::Error for CdrError {}

/// Sequential reader of one XCDR1 message (module documentation).
#[derive(Debug, Clone)]
pub struct CdrReader<'a> {
    data: &'a [u8],
    /// Absolute offset of the next byte (the header included).
    pos: usize,
    little_endian: bool,
}

impl<'a> CdrReader<'a> {
    /// Reads the encapsulation header of `data`; the reader then stands at the first field.
    pub fn new(data: &'a [u8]) -> Result<Self, CdrError> {
        let err = |kind| CdrError { field: "encapsulation", offset: 0, kind };
        if data.len() < ENCAPSULATION_LEN {
            return Err(err(CdrErrorKind::Truncated { needed: ENCAPSULATION_LEN, left: data.len() }));
        }
        let id = u16::from_be_bytes([data[0], data[1]]);
        let little_endian = match id {
            0x0000 => false,
            0x0001 => true,
            other => return Err(err(CdrErrorKind::Encapsulation(other))),
        };
        Ok(Self { data, pos: ENCAPSULATION_LEN, little_endian })
    }

    /// Whether the message is little endian (`CDR_LE`).
    pub fn is_little_endian(&self) -> bool {
        self.little_endian
    }

    /// Offset of the next byte in the message.
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Takes `N` bytes for a primitive of alignment `N` (padding skipped first).
    fn take<const N: usize>(&mut self, field: &'static str) -> Result<[u8; N], CdrError> {
        let misalign = (self.pos - ENCAPSULATION_LEN) % N;
        let start = if misalign == 0 { self.pos } else { self.pos + N - misalign };
        let left = self.data.len().saturating_sub(start);
        let bytes: [u8; N] = self.data.get(start..start + N).and_then(|b| b.try_into().ok()).ok_or(CdrError {
            field,
            offset: start.min(self.data.len()),
            kind: CdrErrorKind::Truncated { needed: N, left },
        })?;
        self.pos = start + N;
        Ok(bytes)
    }

    /// A u32.
    pub fn u32(&mut self, field: &'static str) -> Result<u32, CdrError> {
        let b = self.take::<4>(field)?;
        Ok(if self.little_endian { u32::from_le_bytes(b) } else { u32::from_be_bytes(b) })
    }

    /// An i32.
    pub fn i32(&mut self, field: &'static str) -> Result<i32, CdrError> {
        let b = self.take::<4>(field)?;
        Ok(if self.little_endian { i32::from_le_bytes(b) } else { i32::from_be_bytes(b) })
    }

    /// An f64 (IEEE 754 binary64).
    pub fn f64(&mut self, field: &'static str) -> Result<f64, CdrError> {
        let b = self.take::<8>(field)?;
        Ok(if self.little_endian { f64::from_le_bytes(b) } else { f64::from_be_bytes(b) })
    }

    /// `N` f64 of a fixed-size array (no length prefix).
    pub fn f64_array<const N: usize>(&mut self, field: &'static str) -> Result<[f64; N], CdrError> {
        let mut out = [0.0; N];
        for v in &mut out {
            *v = self.f64(field)?;
        }
        Ok(out)
    }

    /// A string: u32 length counting the NUL, the bytes, the NUL. Borrowed from the message.
    pub fn string(&mut self, field: &'static str) -> Result<&'a str, CdrError> {
        let len = self.u32(field)? as usize;
        let start = self.pos;
        let bad = |msg: String| CdrError { field, offset: start, kind: CdrErrorKind::BadString(msg) };
        if len == 0 {
            return Err(bad("length 0 leaves no room for the terminating NUL".to_owned()));
        }
        let left = self.data.len() - start;
        let bytes = self.data.get(start..start + len).ok_or(CdrError {
            field,
            offset: start,
            kind: CdrErrorKind::Truncated { needed: len, left },
        })?;
        let (nul, text) = bytes.split_last().expect("len ≥ 1");
        if *nul != 0 {
            return Err(bad(format!("its last byte is 0x{nul:02x}, not NUL")));
        }
        let text = std::str::from_utf8(text).map_err(|e| bad(format!("not UTF-8: {e}")))?;
        self.pos = start + len;
        Ok(text)
    }

    /// Checks that nothing but padding to a 4-byte multiple follows the last field.
    pub fn finish(&self) -> Result<(), CdrError> {
        let extra = self.data.len() - self.pos;
        let padded = (self.data.len() - ENCAPSULATION_LEN).is_multiple_of(4) && extra < 4;
        if extra == 0 || padded {
            Ok(())
        } else {
            Err(CdrError { field: "end of message", offset: self.pos, kind: CdrErrorKind::TrailingBytes(extra) })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitives_align_from_the_end_of_the_header_in_both_byte_orders() {
        // LE: u32 7 at 4, then f64 1.5 aligned to offset 12 (8 from the header's end).
        let mut le = vec![0x00, 0x01, 0, 0];
        le.extend(7u32.to_le_bytes());
        le.extend([0xAA; 4]);
        le.extend(1.5f64.to_le_bytes());
        let mut r = CdrReader::new(&le).unwrap();
        assert!(r.is_little_endian());
        assert_eq!(r.u32("a").unwrap(), 7);
        assert_eq!(r.f64("b").unwrap(), 1.5);
        r.finish().unwrap();
        let mut be = vec![0x00, 0x00, 0, 0];
        be.extend((-3i32).to_be_bytes());
        be.extend([0; 4]);
        be.extend((-0.25f64).to_be_bytes());
        let mut r = CdrReader::new(&be).unwrap();
        assert_eq!(r.i32("a").unwrap(), -3);
        assert_eq!(r.f64("b").unwrap(), -0.25);
    }

    #[test]
    fn strings_need_their_nul_and_short_buffers_name_the_field() {
        let mut m = vec![0x00, 0x01, 0, 0];
        m.extend(4u32.to_le_bytes());
        m.extend(b"imu\0");
        let mut r = CdrReader::new(&m).unwrap();
        assert_eq!(r.string("frame_id").unwrap(), "imu");
        let e = r.f64("x").unwrap_err();
        assert_eq!((e.field, e.offset), ("x", 12));
        assert_eq!(e.kind, CdrErrorKind::Truncated { needed: 8, left: 0 });
        let mut bad = vec![0x00, 0x01, 0, 0];
        bad.extend(3u32.to_le_bytes());
        bad.extend(b"imu");
        assert!(matches!(CdrReader::new(&bad).unwrap().string("s").unwrap_err().kind, CdrErrorKind::BadString(_)));
        let mut huge = vec![0x00, 0x01, 0, 0];
        huge.extend(u32::MAX.to_le_bytes());
        assert!(matches!(CdrReader::new(&huge).unwrap().string("s").unwrap_err().kind, CdrErrorKind::Truncated { .. }));
    }

    #[test]
    fn other_encapsulations_and_trailing_bytes_are_refused() {
        assert_eq!(CdrReader::new(&[0x00, 0x07, 0, 0]).unwrap_err().kind, CdrErrorKind::Encapsulation(7));
        assert!(matches!(CdrReader::new(&[0x00]).unwrap_err().kind, CdrErrorKind::Truncated { .. }));
        let m = [0x00, 0x01, 0, 0, 1, 0, 0, 0, 9, 9, 9, 9, 9];
        let mut r = CdrReader::new(&m).unwrap();
        r.u32("a").unwrap();
        assert_eq!(r.finish().unwrap_err().kind, CdrErrorKind::TrailingBytes(5));
        let padded = [0x00, 0x01, 0, 0, 1, 0, 0, 0, 7, 0, 0, 0];
        let mut r = CdrReader::new(&padded).unwrap();
        r.u32("a").unwrap();
        assert!(r.finish().is_err(), "4 bytes are a field, not padding");
    }
}
