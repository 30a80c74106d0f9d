//! Large sample buffers, backed by huge pages where the kernel offers them.
//!
//! A Mark III RGB frame is 170 MB of f32: filled for the first time in 4 KiB
//! pages, its 41,000 page faults cost a reader about as much as decoding the
//! file (perf: a quarter of `read_frame`'s time in the kernel's fault path).
//! Asking for transparent huge pages (Linux `madvise(MADV_HUGEPAGE)`, honoured
//! when `/sys/kernel/mm/transparent_hugepage/enabled` is `always` or
//! `madvise`) before the buffer is first touched makes that 85 faults. It is
//! a hint: where it is refused or unknown, nothing changes but the speed.

/// Buffers below this many bytes are left as they are.
const HUGE_PAGE_MIN_BYTES: usize = 8 << 20;

/// `len` zeros, in huge pages where possible (see the module's text).
pub fn zeroed_f32(len: usize) -> Vec<f32> {
    // calloc of a large block maps fresh zero pages without touching them,
    // so the advice comes before the first fault.
    let mut v = vec![0.0f32; len];
    advise_huge_pages(&mut v);
    v
}

/// `len` f16 zeros, in huge pages where possible.
pub fn zeroed_f16(len: usize) -> Vec<half::f16> {
    let mut v = vec![half::f16::ZERO; len];
    advise_huge_pages(&mut v);
    v
}

#[cfg(target_os = "linux")]
fn advise_huge_pages<T>(v: &mut [T]) {
    let bytes = std::mem::size_of_val(v);
    if bytes < HUGE_PAGE_MIN_BYTES {
        return;
    }
    const HUGE: usize = 2 << 20;
    let start = v.as_mut_ptr() as usize;
    let aligned = start.next_multiple_of(HUGE);
    let end = (start + bytes) & !(HUGE - 1);
    if end > aligned {
        // SAFETY: the range lies inside `v`'s allocation; MADV_HUGEPAGE only
        // changes how the kernel backs those pages, never their contents.
        unsafe {
            libc::madvise(aligned as *mut libc::c_void, end - aligned, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages<T>(_: &mut [T]) {}
