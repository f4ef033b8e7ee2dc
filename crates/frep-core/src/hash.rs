//! A fast, non-cryptographic hasher for the caches and integer-keyed maps of
//! the renderer and the polygonizers: one multiply, xor and rotate per word,
//! where the standard library's SipHash takes tens of instructions. Keys
//! there are tapes, or integers that are already hashes or cell indices; a
//! collision costs only time (the maps compare keys in full), so resistance
//! to crafted collisions is not needed.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// See the module docs. Integers of any width are one step each; bytes
/// are taken eight at a time.
#[derive(Clone, Copy, Debug, Default)]
pub struct FastHasher(u64);

impl FastHasher {
    #[inline]
    fn add(&mut self, v: u64) {
        self.0 = (self.0 ^ v)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .rotate_left(29);
    }
}

impl Hasher for FastHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for c in bytes.chunks(8) {
            let mut b = [0u8; 8];
            b[..c.len()].copy_from_slice(c);
            self.add(u64::from_le_bytes(b));
        }
    }
    #[inline]
    fn write_u8(&mut self, v: u8) {
        self.add(u64::from(v));
    }
    #[inline]
    fn write_u16(&mut self, v: u16) {
        self.add(u64::from(v));
    }
    #[inline]
    fn write_u32(&mut self, v: u32) {
        self.add(u64::from(v));
    }
    #[inline]
    fn write_u64(&mut self, v: u64) {
        self.add(v);
    }
    #[inline]
    fn write_usize(&mut self, v: usize) {
        self.add(v as u64);
    }
}

/// A `HashMap` hashed with [`FastHasher`].
pub type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<FastHasher>>;

#[cfg(test)]
mod tests {
    use super::*;
    use std::hash::Hash;

    fn hash<T: Hash + ?Sized>(t: &T) -> u64 {
        let mut h = FastHasher::default();
        t.hash(&mut h);
        h.finish()
    }

    #[test]
    fn spreads_nearby_keys_and_sees_every_byte() {
        // Consecutive integers land in different buckets of a small table.
        let buckets: std::collections::HashSet<u64> = (0u64..64).map(|k| hash(&k) >> 58).collect();
        assert!(buckets.len() > 32, "{} of 64 buckets", buckets.len());
        // A change in any byte of a key, the last partial word included,
        // changes the hash.
        let base = [7u8; 13];
        for i in 0..13 {
            let mut b = base;
            b[i] ^= 1;
            assert_ne!(hash(&b[..]), hash(&base[..]), "byte {i}");
        }
    }
}
