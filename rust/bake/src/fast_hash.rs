//! A fast hash for the integer keys of spatial grids and edge maps (a
//! multiply and a fold: the keys come from geometry, not from an adversary).

use std::hash::{BuildHasherDefault, Hasher};

/// Builds [`FastHasher`]s for `HashMap`s.
pub type FastHash = BuildHasherDefault<FastHasher>;

/// Multiply-fold hashing of integers.
#[derive(Default)]
pub struct FastHasher(u64);

impl Hasher for FastHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    fn write_u32(&mut self, key: u32) {
        self.write_u64(key as u64);
    }

    fn write_u64(&mut self, key: u64) {
        let x = (self.0.rotate_left(5) ^ key).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        self.0 = x ^ (x >> 29);
    }
}
