//! A tiny, pointer-free, little-endian byte format for FMU states.
//!
//! Writers append fixed-width little-endian numbers and length-prefixed byte strings; readers
//! return an error (never panic) on truncated or malformed input.

/// Appends values to a byte vector.
#[derive(Debug, Default, Clone)]
pub struct ByteWriter {
    /// The bytes written so far.
    pub buf: Vec<u8>,
}

impl ByteWriter {
    /// An empty writer.
    pub fn new() -> Self {
        Self::default()
    }
    /// Appends one byte.
    pub fn u8(&mut self, v: u8) -> &mut Self {
        self.buf.push(v);
        self
    }
    /// Appends a bool as one byte (0 or 1).
    pub fn bool(&mut self, v: bool) -> &mut Self {
        self.u8(v as u8)
    }
    /// Appends a little-endian `u32`.
    pub fn u32(&mut self, v: u32) -> &mut Self {
        self.buf.extend_from_slice(&v.to_le_bytes());
        self
    }
    /// Appends a little-endian `u64`.
    pub fn u64(&mut self, v: u64) -> &mut Self {
        self.buf.extend_from_slice(&v.to_le_bytes());
        self
    }
    /// Appends a little-endian `i64`.
    pub fn i64(&mut self, v: i64) -> &mut Self {
        self.buf.extend_from_slice(&v.to_le_bytes());
        self
    }
    /// Bit-exact (NaN payloads and signed zeros survive).
    pub fn f64(&mut self, v: f64) -> &mut Self {
        self.u64(v.to_bits())
    }
    /// Appends a presence byte, then the value if present.
    pub fn opt_f64(&mut self, v: Option<f64>) -> &mut Self {
        match v {
            Some(x) => self.u8(1).f64(x),
            None => self.u8(0).f64(0.0),
        }
    }
    /// Length (u64) followed by the bytes.
    pub fn bytes(&mut self, v: &[u8]) -> &mut Self {
        self.u64(v.len() as u64);
        self.buf.extend_from_slice(v);
        self
    }
    /// Appends a length-prefixed UTF-8 string.
    pub fn str(&mut self, v: &str) -> &mut Self {
        self.bytes(v.as_bytes())
    }
    /// Appends bytes without a length prefix.
    pub fn raw(&mut self, v: &[u8]) -> &mut Self {
        self.buf.extend_from_slice(v);
        self
    }
    /// The bytes written.
    pub fn into_bytes(self) -> Vec<u8> {
        self.buf
    }
}

/// Reads values written by [`ByteWriter`]; every read checks the remaining length.
#[derive(Debug, Clone)]
pub struct ByteReader<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> ByteReader<'a> {
    /// A reader at the start of `data`.
    pub fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }
    /// Bytes read so far.
    pub fn position(&self) -> usize {
        self.pos
    }
    /// Bytes left.
    pub fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }
    /// The next `n` bytes; `what` names the field in the error.
    pub fn raw(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        if n > self.remaining() {
            return Err(format!(
                "truncated state: {what} needs {n} bytes at offset {}, only {} left",
                self.pos,
                self.remaining()
            ));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    /// Reads one byte.
    pub fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.raw(1, what)?[0])
    }
    /// Reads a bool written by [`ByteWriter::bool`].
    pub fn bool(&mut self, what: &str) -> Result<bool, String> {
        match self.u8(what)? {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(format!("corrupt state: {what} is {b}, expected 0 or 1")),
        }
    }
    /// Reads a little-endian `u32`.
    pub fn u32(&mut self, what: &str) -> Result<u32, String> {
        let b = self.raw(4, what)?;
        Ok(u32::from_le_bytes(b.try_into().expect("4 bytes")))
    }
    /// Reads a little-endian `u64`.
    pub fn u64(&mut self, what: &str) -> Result<u64, String> {
        let b = self.raw(8, what)?;
        Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
    }
    /// Reads a little-endian `i64`.
    pub fn i64(&mut self, what: &str) -> Result<i64, String> {
        Ok(self.u64(what)? as i64)
    }
    /// Reads an `f64` (bit-exact).
    pub fn f64(&mut self, what: &str) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64(what)?))
    }
    /// Reads an optional `f64` written by [`ByteWriter::opt_f64`].
    pub fn opt_f64(&mut self, what: &str) -> Result<Option<f64>, String> {
        let some = self.bool(what)?;
        let v = self.f64(what)?;
        Ok(some.then_some(v))
    }
    /// Reads a length-prefixed byte string.
    pub fn bytes(&mut self, what: &str) -> Result<&'a [u8], String> {
        let n = self.u64(what)?;
        let n = usize::try_from(n).map_err(|_| format!("corrupt state: {what} length {n}"))?;
        self.raw(n, what)
    }
    /// Reads a length-prefixed UTF-8 string.
    pub fn str(&mut self, what: &str) -> Result<&'a str, String> {
        std::str::from_utf8(self.bytes(what)?)
            .map_err(|_| format!("corrupt state: {what} is not UTF-8"))
    }
    /// Fails unless every byte was consumed.
    pub fn finish(&self, what: &str) -> Result<(), String> {
        if self.remaining() == 0 {
            Ok(())
        } else {
            Err(format!(
                "corrupt state: {} unexpected trailing bytes after {what}",
                self.remaining()
            ))
        }
    }
}

/// FNV-1a, 64 bit: the state blob's integrity check (not a cryptographic hash).
pub fn fnv1a64(data: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_truncation() {
        let mut w = ByteWriter::new();
        w.u8(7)
            .bool(true)
            .u32(0xdead_beef)
            .u64(u64::MAX)
            .i64(-5)
            .f64(-0.0)
            .opt_f64(Some(1.5))
            .opt_f64(None)
            .str("héllo")
            .bytes(&[1, 2, 3]);
        let bytes = w.into_bytes();
        let mut r = ByteReader::new(&bytes);
        assert_eq!(r.u8("a").unwrap(), 7);
        assert!(r.bool("b").unwrap());
        assert_eq!(r.u32("c").unwrap(), 0xdead_beef);
        assert_eq!(r.u64("d").unwrap(), u64::MAX);
        assert_eq!(r.i64("e").unwrap(), -5);
        assert_eq!(r.f64("f").unwrap().to_bits(), (-0.0f64).to_bits());
        assert_eq!(r.opt_f64("g").unwrap(), Some(1.5));
        assert_eq!(r.opt_f64("h").unwrap(), None);
        assert_eq!(r.str("i").unwrap(), "héllo");
        assert_eq!(r.bytes("j").unwrap(), &[1, 2, 3]);
        r.finish("all").unwrap();
        for cut in 0..bytes.len() {
            let mut r = ByteReader::new(&bytes[..cut]);
            let res = (|| -> Result<(), String> {
                r.u8("a")?;
                r.bool("b")?;
                r.u32("c")?;
                r.u64("d")?;
                r.i64("e")?;
                r.f64("f")?;
                r.opt_f64("g")?;
                r.opt_f64("h")?;
                r.str("i")?;
                r.bytes("j")?;
                Ok(())
            })();
            assert!(res.is_err(), "cut at {cut} must fail");
        }
    }

    #[test]
    fn huge_length_prefix_is_an_error() {
        let mut w = ByteWriter::new();
        w.u64(u64::MAX);
        let b = w.into_bytes();
        assert!(ByteReader::new(&b).bytes("x").is_err());
    }

    #[test]
    fn fnv_known_values() {
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
    }
}
