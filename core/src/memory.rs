//! How the process's allocator keeps memory, for the `taut` binary and the benchmarks that
//! time what it does.

/// Asks glibc's allocator to keep the memory it was given for the next allocation instead of
/// handing it back to the system at every free: blocks up to 32 MB come from its heap rather
/// than from a fresh mapping each, and the heap is not trimmed below 1 GB of free space.
///
/// A topology edit rebuilds every subdivision level, tens of MB on a large cage; by default
/// glibc maps each large array afresh and unmaps it when dropped, so a third of a fresh
/// Catmull–Clark level 3 went to the kernel faulting in and clearing new pages
/// (`docs/subdivision.md`). Blocks above 32 MB (a huge file being read) are still mapped on their
/// own and grow in place, so reading one takes memory in proportion to it. Elsewhere than Linux
/// with glibc this does nothing. Call it first thing in `main`, before any thread starts.
#[allow(unsafe_code)]
pub fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets two of glibc's allocation thresholds; it is called before any
    // other thread exists, and a refused value leaves glibc's default in place.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 1 << 30);
    }
}
