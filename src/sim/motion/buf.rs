//! A buffer of a length chosen at run time, held inline up to `N` elements and on the heap
//! above: the closed form's per-term and per-mass arrays. The paper's structures (a few
//! masses) keep every buffer on the stack, as fixed arrays did; a larger structure pays one
//! allocation a buffer, small beside the work on its terms (BENCHMARKS.md, "Cost per degree
//! of freedom").

use std::ops::{Deref, DerefMut};

/// Terms held inline (conjugate pairs count once): the terms of 8 masses.
pub const INLINE_TERMS: usize = 16;

/// Masses held inline.
pub const INLINE_MASSES: usize = INLINE_TERMS / 2;

/// `len` elements of `T`, inline when `len <= N`.
#[derive(Debug)]
pub struct Buf<T: Copy + Default, const N: usize> {
    len: usize,
    inline: [T; N],
    heap: Vec<T>,
}

impl<T: Copy + Default, const N: usize> Buf<T, N> {
    /// `len` default elements (zeros).
    #[inline]
    pub fn zeros(len: usize) -> Self {
        let heap = if len <= N { Vec::new() } else { vec![T::default(); len] };
        Buf { len, inline: [T::default(); N], heap }
    }

    /// Makes the length `len`, keeping the storage (the elements' values are whatever was
    /// there, or zeros: the caller overwrites them).
    #[inline]
    pub fn set_len(&mut self, len: usize) {
        if len > N {
            self.heap.resize(len, T::default());
        } else if !self.heap.is_empty() {
            self.heap = Vec::new();
        }
        self.len = len;
    }

    /// Whether the elements live on the heap.
    pub fn spilled(&self) -> bool {
        self.len > N
    }
}

impl<T: Copy + Default, const N: usize> Clone for Buf<T, N> {
    /// A copy of the inline array and no call for the empty heap part (hot: points are
    /// cloned in every root search).
    #[inline]
    fn clone(&self) -> Self {
        let heap = if self.len <= N { Vec::new() } else { self.heap.clone() };
        Buf { len: self.len, inline: self.inline, heap }
    }
}

impl<T: Copy + Default, const N: usize> Deref for Buf<T, N> {
    type Target = [T];
    #[inline(always)]
    fn deref(&self) -> &[T] {
        if self.len <= N {
            &self.inline[..self.len]
        } else {
            &self.heap
        }
    }
}

impl<T: Copy + Default, const N: usize> DerefMut for Buf<T, N> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [T] {
        if self.len <= N {
            &mut self.inline[..self.len]
        } else {
            &mut self.heap
        }
    }
}

/// Per-term complex numbers (`c_r`, `e^{lambda_r t}`, ...).
pub type Terms<T> = Buf<T, INLINE_TERMS>;

/// Per-mass real numbers (accelerations, forced-response coefficients, ...).
pub type PerMass = Buf<f64, INLINE_MASSES>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_buffer_holds_its_length_inline_or_on_the_heap_and_clones_alike() {
        for len in [0, 1, 8, 9, 40] {
            let mut b: Buf<f64, 8> = Buf::zeros(len);
            assert_eq!(b.len(), len);
            assert_eq!(b.spilled(), len > 8);
            for (i, e) in b.iter_mut().enumerate() {
                *e = i as f64;
            }
            let c = b.clone();
            assert_eq!(&c[..], &b[..]);
            assert!(c.iter().enumerate().all(|(i, &e)| e == i as f64));
        }
    }
}
