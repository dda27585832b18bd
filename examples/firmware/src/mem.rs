//! Size-first memory routines: `memcpy`, `memset` and the ARM EABI entry
//! points the compiler calls for them, one byte at a time.
//!
//! The C library a firmware links decides how these are built; newlib-nano,
//! for one, builds them for size. Without a C library the linker takes
//! them from `compiler_builtins`, whose versions are built for speed (word
//! copies with alignment fix-ups): about 1.4 KB of flash on this node,
//! against about 90 bytes here. A node copies a few hundred bytes per
//! frame at most, where the byte loop costs microseconds; a port that
//! wants the fast ones deletes this module. The footprint script prints
//! the flash with these routines (the figure recorded in `budget.txt`).
//!
//! Reads and writes are volatile so that the compiler cannot turn the
//! loops back into calls of the routine being defined.

use core::ptr::{read_volatile, write_volatile};

/// Copies `n` bytes forwards, one at a time. Every public routine below
/// calls these private loops, never `memcpy` and the others by name: the
/// compiler reads a call of a function named `memcpy` as its own memcpy
/// and lowers it to `__aeabi_memcpy`, so `__aeabi_memcpy` calling
/// `memcpy` became a jump to itself (the firmware hung at its first copy).
///
/// # Safety
///
/// `src` readable and `dest` writable for `n` bytes; `dest` at or below
/// `src` when they overlap.
#[inline(never)]
unsafe fn copy_forward(dest: *mut u8, src: *const u8, n: usize) {
    let mut i = 0;
    while i < n {
        // SAFETY: `i < n`, within both buffers by the caller's contract.
        unsafe { write_volatile(dest.add(i), read_volatile(src.add(i))) };
        i += 1;
    }
}

/// Copies `n` bytes backwards (an overlapping tail is read before it is
/// written).
///
/// # Safety
///
/// `src` readable and `dest` writable for `n` bytes.
#[inline(never)]
unsafe fn copy_backward(dest: *mut u8, src: *const u8, n: usize) {
    let mut i = n;
    while i > 0 {
        i -= 1;
        // SAFETY: `i < n`, within both buffers by the caller's contract.
        unsafe { write_volatile(dest.add(i), read_volatile(src.add(i))) };
    }
}

/// Sets `n` bytes at `dest` to `c`.
///
/// # Safety
///
/// `dest` writable for `n` bytes.
#[inline(never)]
unsafe fn fill(dest: *mut u8, c: u8, n: usize) {
    let mut i = 0;
    while i < n {
        // SAFETY: `i < n`, within the buffer by the caller's contract.
        unsafe { write_volatile(dest.add(i), c) };
        i += 1;
    }
}

/// Compares `n` bytes: the difference of the first unequal pair, or 0.
///
/// # Safety
///
/// Both readable for `n` bytes.
#[inline(never)]
unsafe fn compare(a: *const u8, b: *const u8, n: usize) -> i32 {
    let mut i = 0;
    while i < n {
        // SAFETY: `i < n`, within both buffers by the caller's contract.
        let (x, y) = unsafe { (read_volatile(a.add(i)), read_volatile(b.add(i))) };
        if x != y {
            return i32::from(x) - i32::from(y);
        }
        i += 1;
    }
    0
}

/// Copies `n` bytes from `src` to `dest` (the C `memcpy`).
///
/// # Safety
///
/// As C's: `src` readable and `dest` writable for `n` bytes, the two not
/// overlapping.
#[no_mangle]
pub unsafe extern "C" fn memcpy(dest: *mut u8, src: *const u8, n: usize) -> *mut u8 {
    // SAFETY: the caller's contract is the loop's.
    unsafe { copy_forward(dest, src, n) };
    dest
}

/// Copies `n` bytes from `src` to `dest`, which may overlap (the C
/// `memmove`).
///
/// # Safety
///
/// As C's: `src` readable and `dest` writable for `n` bytes.
#[no_mangle]
pub unsafe extern "C" fn memmove(dest: *mut u8, src: *const u8, n: usize) -> *mut u8 {
    // SAFETY: the caller's contract.
    unsafe { move_bytes(dest, src, n) };
    dest
}

/// Copies `n` bytes that may overlap: forwards when `dest` is at or below
/// `src`, backwards otherwise.
///
/// # Safety
///
/// `src` readable and `dest` writable for `n` bytes.
unsafe fn move_bytes(dest: *mut u8, src: *const u8, n: usize) {
    // SAFETY: the caller's contract, in the direction that reads an
    // overlapping part before writing it.
    unsafe {
        if (dest as usize) <= (src as usize) {
            copy_forward(dest, src, n);
        } else {
            copy_backward(dest, src, n);
        }
    }
}

/// Sets `n` bytes at `dest` to `c` (the C `memset`).
///
/// # Safety
///
/// As C's: `dest` writable for `n` bytes.
#[no_mangle]
pub unsafe extern "C" fn memset(dest: *mut u8, c: i32, n: usize) -> *mut u8 {
    // SAFETY: the caller's contract. The byte is C's `(unsigned char)c`.
    unsafe { fill(dest, c as u8, n) };
    dest
}

/// Compares `n` bytes (the C `memcmp`).
///
/// # Safety
///
/// As C's: both readable for `n` bytes.
#[no_mangle]
pub unsafe extern "C" fn memcmp(a: *const u8, b: *const u8, n: usize) -> i32 {
    // SAFETY: the same contract.
    unsafe { compare(a, b, n) }
}

/// `bcmp`, which the compiler calls for equality-only comparisons.
///
/// # Safety
///
/// As [`memcmp`].
#[no_mangle]
pub unsafe extern "C" fn bcmp(a: *const u8, b: *const u8, n: usize) -> i32 {
    // SAFETY: the same contract.
    unsafe { compare(a, b, n) }
}

/// The ARM EABI's names for the same routines (the `4`/`8` forms promise
/// aligned pointers, which the byte loops do not need; `memset`'s EABI
/// forms take the length before the value).
macro_rules! aeabi {
    ($($name:ident($($arg:ident: $ty:ty),*) => $body:expr;)*) => {$(
        #[doc = concat!("The ARM EABI `", stringify!($name), "`.")]
        ///
        /// # Safety
        ///
        /// As the C routine it calls.
        #[no_mangle]
        pub unsafe extern "C" fn $name($($arg: $ty),*) {
            // SAFETY: the same contract as the routine called.
            unsafe { $body };
        }
    )*};
}

aeabi! {
    __aeabi_memcpy(d: *mut u8, s: *const u8, n: usize) => copy_forward(d, s, n);
    __aeabi_memcpy4(d: *mut u8, s: *const u8, n: usize) => copy_forward(d, s, n);
    __aeabi_memcpy8(d: *mut u8, s: *const u8, n: usize) => copy_forward(d, s, n);
    __aeabi_memmove(d: *mut u8, s: *const u8, n: usize) => move_bytes(d, s, n);
    __aeabi_memmove4(d: *mut u8, s: *const u8, n: usize) => move_bytes(d, s, n);
    __aeabi_memmove8(d: *mut u8, s: *const u8, n: usize) => move_bytes(d, s, n);
    __aeabi_memset(d: *mut u8, n: usize, c: i32) => fill(d, c as u8, n);
    __aeabi_memset4(d: *mut u8, n: usize, c: i32) => fill(d, c as u8, n);
    __aeabi_memset8(d: *mut u8, n: usize, c: i32) => fill(d, c as u8, n);
    __aeabi_memclr(d: *mut u8, n: usize) => fill(d, 0, n);
    __aeabi_memclr4(d: *mut u8, n: usize) => fill(d, 0, n);
    __aeabi_memclr8(d: *mut u8, n: usize) => fill(d, 0, n);
}
