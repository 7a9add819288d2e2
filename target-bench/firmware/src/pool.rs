//! Memory handed out by size at boot: one build serves every image size and band height, and
//! what a run takes from a pool is exactly what a firmware sized for that run would hold in
//! statics (the runner counts the pools' used part as RAM, not their capacity).

use crate::Failure;

/// A `'static` slice from which buffers are taken, front first, never given back.
pub struct Pool<T: 'static> {
    free: &'static mut [T],
    capacity: usize,
}

impl<T> Pool<T> {
    /// A pool over `all`.
    pub fn new(all: &'static mut [T]) -> Self {
        let capacity = all.len();
        Pool {
            free: all,
            capacity,
        }
    }

    /// The next `n` elements, for `what` (named in the error).
    pub fn take(&mut self, n: usize, what: &'static str) -> Result<&'static mut [T], Failure> {
        let free = core::mem::take(&mut self.free);
        if n > free.len() {
            let left = free.len();
            self.free = free;
            return Err(Failure::OutOfMemory {
                what,
                needed: n,
                free: left,
            });
        }
        let (taken, rest) = free.split_at_mut(n);
        self.free = rest;
        Ok(taken)
    }

    /// Bytes handed out.
    pub fn used_bytes(&self) -> usize {
        (self.capacity - self.free.len()) * core::mem::size_of::<T>()
    }

    /// Bytes of the whole pool.
    pub fn capacity_bytes(&self) -> usize {
        self.capacity * core::mem::size_of::<T>()
    }
}
