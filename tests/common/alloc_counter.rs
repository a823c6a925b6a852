//! A counting global allocator for the "does not allocate" tests. A test crate that declares
//! `#[path = "common/alloc_counter.rs"] mod alloc_counter;` installs it as its
//! global allocator. Only the thread inside [`allocations_during`] is counted: the test
//! harness's own thread may allocate meanwhile (its first blocking wait for the test's result
//! does, when the machine is loaded enough that it comes while the test is counting).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static COUNT: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    // Const-initialised and without a destructor: reading it never allocates.
    static ON: Cell<bool> = const { Cell::new(false) };
}

/// Whether the calling thread is being counted.
fn counting() -> bool {
    ON.try_with(Cell::get).unwrap_or(false)
}

// SAFETY: every method forwards to the system allocator, which meets GlobalAlloc's contract;
// counting does not allocate.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        if counting() {
            COUNT.fetch_add(1, Ordering::SeqCst);
        }
        // SAFETY: the caller's layout meets GlobalAlloc::alloc's contract (passed on unchanged).
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        // SAFETY: p was allocated by this allocator (hence by System) with layout l.
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        if counting() {
            COUNT.fetch_add(1, Ordering::SeqCst);
        }
        // SAFETY: p was allocated by this allocator (hence by System) with layout l; n is the
        // caller's valid new size.
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Runs `f` and returns how many allocations (and reallocations) it made.
pub fn allocations_during<R>(f: impl FnOnce() -> R) -> (usize, R) {
    COUNT.store(0, Ordering::SeqCst);
    ON.with(|on| on.set(true));
    let r = f();
    ON.with(|on| on.set(false));
    (COUNT.swap(0, Ordering::SeqCst), r)
}
