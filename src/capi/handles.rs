//! Handles and argument checks.
//!
//! A handle is a small fixed-size [`Slot`]: a state word and a box holding the payload (the
//! mesh, the boundary conditions, the solver). Three rules make a handle safe to misuse:
//!
//! * **Never reused (tombstones).** `_free` drops the payload but never the slot: the slot stays
//!   allocated, marked dead, so its address is never handed out again while the process lives.
//!   A stale handle therefore always points at its own tombstone and is refused, even after
//!   later handles were created (a freed address reused by the allocator would otherwise make a
//!   stale pointer indistinguishable from a live one: a generation stored in the object cannot
//!   help, as the pointer itself carries none). The cost is the slot and its registry entry,
//!   about 120 bytes per handle ever created (118 measured over a million create/free pairs),
//!   kept until the process exits.
//! * **Registered.** Every slot's address and type are in a registry, so a pointer meshmove never
//!   made, or a handle of another type, is refused before it is dereferenced.
//! * **Busy, not racing.** Every call acquires the handle's state word with one atomic
//!   compare-and-swap and releases it when it returns (also on an error or a caught panic: the
//!   guard's `Drop`). Calls that only read a handle share it; a call that changes it (or frees
//!   it) needs it alone. A call that finds the handle taken returns `MESHMOVE_STATUS_BUSY`
//!   immediately and changes nothing: it never waits, never races. The one exception is a
//!   solver's cancellation request (`cancel_of`), an atomic flag in the slot beside the state
//!   word, which another thread sets without acquiring the handle. A call that panics while it
//!   holds a handle alone leaves it poisoned: every later call but `_free` is refused.
//! * **Fork-safe.** `pthread_atfork` handlers (registered before the registry is first locked)
//!   take the registry's lock before `fork()` and release it in the parent and the child, so a
//!   child never inherits it held by a thread it does not have: it can always create and free
//!   handles. A handle in use by a call at the moment of the fork is, in the child, refused by
//!   every call but `_free` (the call that held it does not exist there, and the payload may be
//!   half-changed); `_free` accepts it and leaks its payload rather than dropping memory that
//!   may be inconsistent.

use super::error::CError;
use super::status::meshmove_status;
use crate::solver::Cancel;
use std::any::TypeId;
use std::cell::UnsafeCell;
use std::collections::HashMap;
use std::ffi::{c_char, CStr};
use std::ops::{Deref, DerefMut};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Mutex;

/// State word values: 0 idle, 1.. that many readers, `WRITER` one writer, `DEAD` freed,
/// `POISONED` a call that changed the handle panicked (it may be half-changed: only `_free` is
/// accepted).
const WRITER: u32 = u32::MAX - 1;
const DEAD: u32 = u32::MAX;
const POISONED: u32 = u32::MAX - 2;
/// In a forked child: the handle was in use when the process forked (only `_free` accepted,
/// which leaks the payload).
const FORKED: u32 = u32::MAX - 3;

/// What a C handle points at: the state word, the payload (`None` once freed) and, for a
/// solver, its cancellation request (reached without acquiring the handle, so another thread
/// can cancel the call that holds it).
pub(crate) struct Slot<T> {
    state: AtomicU32,
    payload: UnsafeCell<Option<Box<T>>>,
    cancel: Option<Cancel>,
}

// SAFETY: the payload is only reached through `Shared` (shared references, many readers) or
// `Exclusive` (one mutable reference), which the state word hands out exclusively of each other;
// payloads are `Send + Sync` (plain data, and the solver's pool).
unsafe impl<T: Send + Sync> Sync for Slot<T> {}

impl<T> Slot<T> {
    pub(crate) fn new(payload: T) -> Self {
        Slot { state: AtomicU32::new(0), payload: UnsafeCell::new(Some(Box::new(payload))), cancel: None }
    }

    /// A slot whose call can be cancelled from another thread through `cancel`.
    pub(crate) fn cancellable(payload: T, cancel: Cancel) -> Self {
        Slot { cancel: Some(cancel), ..Slot::new(payload) }
    }
}

/// A type handed to C as an opaque pointer: a newtype over its `Slot`.
pub(crate) trait Handle: Sized + 'static {
    type Payload: Send + Sync + 'static;
    const NAME: &'static str;
    fn slot(&self) -> &Slot<Self::Payload>;
    fn from_slot(slot: Slot<Self::Payload>) -> Self;
}

/// What the registry holds of a slot: its type, its name and its state word (slots are never
/// freed, so the reference stays valid).
type Entry = (TypeId, &'static str, &'static AtomicU32);
type Registry = Option<HashMap<usize, Entry>>;

/// Address of every slot ever handed out (live or tombstone), with its type and state word.
static SLOTS: Mutex<Registry> = Mutex::new(None);

fn slots<R>(f: impl FnOnce(&mut HashMap<usize, Entry>) -> R) -> R {
    super::fork::register_handlers();
    let mut g = SLOTS.lock().unwrap_or_else(|p| p.into_inner());
    f(g.get_or_insert_with(HashMap::new))
}

thread_local! {
    /// The registry's lock, held by the forking thread from the `prepare` handler of
    /// `pthread_atfork` until the `parent` or `child` handler.
    static HELD: std::cell::RefCell<Option<std::sync::MutexGuard<'static, Registry>>> =
        const { std::cell::RefCell::new(None) };
}

/// Before `fork()`: takes the registry's lock (no thread holds it while the process forks).
pub(crate) fn lock_for_fork() {
    let g = SLOTS.lock().unwrap_or_else(|p| p.into_inner());
    HELD.with(|h| *h.borrow_mut() = Some(g));
}

/// After `fork()`, in the parent: releases the registry's lock.
pub(crate) fn unlock_in_parent() {
    HELD.with(|h| drop(h.borrow_mut().take()));
}

/// After `fork()`, in the child (one thread): every handle a call held at the fork is marked
/// `FORKED` (that call does not exist here), then the registry's lock is released.
pub(crate) fn unlock_in_child() {
    HELD.with(|h| {
        let mut held = h.borrow_mut().take();
        if let Some(map) = held.as_mut().and_then(|g| g.as_mut()) {
            for (_, _, state) in map.values() {
                let now = state.load(Ordering::Acquire);
                if now != 0 && now != DEAD && now != POISONED {
                    state.store(FORKED, Ordering::Release);
                }
            }
        }
        drop(held);
    });
}

/// Boxes `payload` in a new slot, registers it and stores it in `*out`.
///
/// # Safety
/// `out` must have passed `check_out` (not NULL, aligned) and be writable.
pub(crate) unsafe fn hand_out<T: Handle>(payload: T::Payload, out: *mut *mut T) -> Result<(), CError> {
    // SAFETY: this function's contract.
    unsafe { hand_out_slot(Slot::new(payload), out) }
}

/// As `hand_out`, for a slot made by the caller.
///
/// # Safety
/// As `hand_out`.
pub(crate) unsafe fn hand_out_slot<T: Handle>(slot: Slot<T::Payload>, out: *mut *mut T) -> Result<(), CError> {
    let p = Box::into_raw(Box::new(T::from_slot(slot)));
    // SAFETY: `p` comes from `Box::into_raw` and is never freed (slots are tombstones).
    let state: &'static AtomicU32 = unsafe { &(*p).slot().state };
    slots(|m| m.insert(p as usize, (TypeId::of::<T>(), T::NAME, state)));
    // SAFETY: `out` is not NULL, aligned and writable (this function's contract).
    unsafe { *out = p };
    Ok(())
}

/// Checks `out` before any work: not NULL, aligned; `*out` is set to NULL.
///
/// # Safety
/// `out` must be NULL (an error) or writable.
pub(crate) unsafe fn check_out<T>(out: *mut *mut T, what: &str) -> Result<(), CError> {
    if out.is_null() {
        return Err(CError::null(what));
    }
    check_aligned(out, what)?;
    // SAFETY: not NULL and aligned; the caller guarantees it is writable.
    unsafe { *out = std::ptr::null_mut() };
    Ok(())
}

/// The slot behind `p`, once the registry says `p` is a slot of type `T`.
fn slot<'a, T: Handle>(p: *const T, what: &str) -> Result<&'a Slot<T::Payload>, CError> {
    if p.is_null() {
        return Err(CError::null(what));
    }
    match slots(|m| m.get(&(p as usize)).copied()) {
        Some((t, _, _)) if t == TypeId::of::<T>() => {}
        Some((_, name, _)) => {
            return Err(CError::new(
                meshmove_status::InvalidHandle,
                format!("`{what}` is a {name} handle, not a {}", T::NAME),
            ))
        }
        None => {
            return Err(CError::new(
                meshmove_status::InvalidHandle,
                format!("`{what}` is not a {} handle made by meshmove", T::NAME),
            ))
        }
    }
    // SAFETY: registered slots are never freed, and this one is a `T`.
    Ok(unsafe { (*p).slot() })
}

fn freed<T: Handle>(what: &str) -> CError {
    CError::new(meshmove_status::InvalidHandle, format!("`{what}` is a {} handle that was already freed", T::NAME))
}

fn poisoned<T: Handle>(what: &str) -> CError {
    CError::new(
        meshmove_status::InvalidHandle,
        format!("`{what}` ({}) was left unusable by an internal error (PANIC) in an earlier call; free it", T::NAME),
    )
}

/// The error for a handle whose state word is `now` (not idle).
fn taken<T: Handle>(now: u32, what: &str) -> CError {
    match now {
        DEAD => freed::<T>(what),
        POISONED => poisoned::<T>(what),
        FORKED => forked::<T>(what),
        _ => busy::<T>(what),
    }
}

fn forked<T: Handle>(what: &str) -> CError {
    CError::new(
        meshmove_status::InvalidHandle,
        format!(
            "`{what}` ({}) was in use by another thread when this process forked; in the child it can only be freed",
            T::NAME
        ),
    )
}

fn busy<T: Handle>(what: &str) -> CError {
    CError::new(
        meshmove_status::Busy,
        format!(
            "`{what}` ({}) is in use by a call on another thread; one handle must not be used by two threads at once",
            T::NAME
        ),
    )
}

/// A handle acquired for reading (shared with other readers); released on drop.
pub(crate) struct Shared<'a, T> {
    state: &'a AtomicU32,
    value: &'a T,
}

impl<T> Deref for Shared<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.value
    }
}

impl<T> Drop for Shared<'_, T> {
    fn drop(&mut self) {
        self.state.fetch_sub(1, Ordering::Release);
    }
}

/// A handle acquired alone (for a call that changes it); released on drop.
pub(crate) struct Exclusive<'a, T> {
    state: &'a AtomicU32,
    value: &'a mut T,
}

impl<T> Deref for Exclusive<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.value
    }
}

impl<T> DerefMut for Exclusive<'_, T> {
    fn deref_mut(&mut self) -> &mut T {
        self.value
    }
}

impl<T> Drop for Exclusive<'_, T> {
    fn drop(&mut self) {
        // Unwinding from a panic: the payload may be half-changed, so no later call may use it.
        let next = if std::thread::panicking() { POISONED } else { 0 };
        self.state.store(next, Ordering::Release);
    }
}

/// Acquires a handle for a call that only reads it.
pub(crate) fn get<'a, T: Handle>(p: *const T, what: &str) -> Result<Shared<'a, T::Payload>, CError> {
    let s = slot(p, what)?;
    let mut cur = s.state.load(Ordering::Relaxed);
    loop {
        match cur {
            n if n >= FORKED - 1 => return Err(taken::<T>(n, what)),
            n => match s.state.compare_exchange_weak(n, n + 1, Ordering::Acquire, Ordering::Relaxed) {
                Ok(_) => break,
                Err(now) => cur = now,
            },
        }
    }
    // SAFETY: the state word now counts this reader, so no writer holds or takes the payload.
    match unsafe { (*s.payload.get()).as_deref() } {
        Some(value) => Ok(Shared { state: &s.state, value }),
        None => {
            s.state.fetch_sub(1, Ordering::Release);
            Err(freed::<T>(what))
        }
    }
}

/// Acquires a handle alone, for a call that changes it.
pub(crate) fn get_mut<'a, T: Handle>(p: *mut T, what: &str) -> Result<Exclusive<'a, T::Payload>, CError> {
    let s = slot(p, what)?;
    if let Err(now) = s.state.compare_exchange(0, WRITER, Ordering::Acquire, Ordering::Relaxed) {
        return Err(taken::<T>(now, what));
    }
    // SAFETY: the state word is `WRITER`: this call alone reaches the payload until the guard drops.
    match unsafe { (*s.payload.get()).as_deref_mut() } {
        Some(value) => Ok(Exclusive { state: &s.state, value }),
        None => {
            s.state.store(DEAD, Ordering::Release);
            Err(freed::<T>(what))
        }
    }
}

/// The cancellation request of the live handle `p`, without acquiring it (the one access a
/// handle busy in another thread's call allows).
pub(crate) fn cancel_of<T: Handle>(p: *const T, what: &str) -> Result<Cancel, CError> {
    let s = slot(p, what)?;
    match s.state.load(Ordering::Acquire) {
        DEAD => Err(freed::<T>(what)),
        _ => s.cancel.clone().ok_or_else(|| CError::arg(format!("`{what}` ({}) has no call to cancel", T::NAME))),
    }
}

/// Frees a handle's payload and leaves its slot as a tombstone; NULL is fine. A stale, foreign
/// or busy handle is an error and nothing is freed.
pub(crate) fn free<T: Handle>(p: *mut T, what: &str) -> Result<(), CError> {
    if p.is_null() {
        return Ok(());
    }
    let s = slot(p, what)?;
    let idle = |from: u32| s.state.compare_exchange(from, WRITER, Ordering::Acquire, Ordering::Relaxed);
    let mut forked = false;
    if let Err(now) = idle(0) {
        // A poisoned handle can still be freed, and so can one a forked child inherited busy.
        forked = now == FORKED;
        if !(now == POISONED || forked) || idle(now).is_err() {
            return Err(taken::<T>(now, what));
        }
    }
    // SAFETY: the state word is `WRITER`: no other call reaches the payload.
    let payload = unsafe { (*s.payload.get()).take() };
    s.state.store(DEAD, Ordering::Release);
    if forked {
        // A call was changing it when the process forked: its memory may be inconsistent.
        std::mem::forget(payload);
    } else {
        drop(payload);
    }
    Ok(())
}

pub(crate) fn check_aligned<T>(p: *const T, what: &str) -> Result<(), CError> {
    if (p as usize) % std::mem::align_of::<T>() != 0 {
        return Err(CError::arg(format!("`{what}` is not aligned for its type")));
    }
    Ok(())
}

/// A count argument: not negative.
pub(crate) fn count(n: i32, what: &str) -> Result<usize, CError> {
    usize::try_from(n).map_err(|_| CError::arg(format!("`{what}` is {n}; it must not be negative")))
}

/// `len` elements at `p`; NULL is allowed only when `len` is 0.
///
/// # Safety
/// A non-NULL `p` must point to `len` initialised elements that stay valid and unchanged for `'a`.
pub(crate) unsafe fn slice<'a, T>(p: *const T, len: usize, what: &str) -> Result<&'a [T], CError> {
    if len == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(CError::null(what));
    }
    check_aligned(p, what)?;
    // SAFETY: not NULL, aligned, `len` elements (this function's contract).
    Ok(unsafe { std::slice::from_raw_parts(p, len) })
}

/// `len` writable elements at `p`; NULL is allowed only when `len` is 0.
///
/// # Safety
/// A non-NULL `p` must point to `len` initialised elements, writable and not otherwise accessed
/// for `'a`.
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, len: usize, what: &str) -> Result<&'a mut [T], CError> {
    if len == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(CError::null(what));
    }
    check_aligned(p, what)?;
    // SAFETY: not NULL, aligned, `len` writable elements (this function's contract).
    Ok(unsafe { std::slice::from_raw_parts_mut(p, len) })
}

/// A NUL-terminated UTF-8 string argument.
///
/// # Safety
/// `p` must be NULL (an error) or point to a NUL-terminated string valid for `'a`.
pub(crate) unsafe fn path<'a>(p: *const c_char, what: &str) -> Result<&'a str, CError> {
    if p.is_null() {
        return Err(CError::null(what));
    }
    // SAFETY: not NULL; the caller guarantees a NUL-terminated string.
    unsafe { CStr::from_ptr(p) }.to_str().map_err(|_| CError::arg(format!("`{what}` is not valid UTF-8")))
}

/// The first index of the caller's vertex numbering: 0 (C) or 1 (Fortran).
pub(crate) fn index_base(b: i32) -> Result<i32, CError> {
    match b {
        0 | 1 => Ok(b),
        _ => Err(CError::arg(format!("index base is {b}; it must be 0 (C) or 1 (Fortran)"))),
    }
}

/// Writes one value to a required output.
///
/// # Safety
/// `p` must be NULL (an error) or valid for writing one `T`.
pub(crate) unsafe fn write_out<T>(p: *mut T, v: T, what: &str) -> Result<(), CError> {
    if p.is_null() {
        return Err(CError::null(what));
    }
    check_aligned(p, what)?;
    // SAFETY: not NULL, aligned; the caller guarantees it is writable.
    unsafe { p.write(v) };
    Ok(())
}

/// Writes one value to an optional output (NULL: nothing is written).
///
/// # Safety
/// `p` must be NULL or valid for writing one `T`.
pub(crate) unsafe fn write_opt<T>(p: *mut T, v: T, what: &str) -> Result<(), CError> {
    if p.is_null() {
        return Ok(());
    }
    // SAFETY: not NULL; the caller guarantees it is writable.
    unsafe { write_out(p, v, what) }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Thing(Slot<Vec<u8>>);
    impl Handle for Thing {
        type Payload = Vec<u8>;
        const NAME: &'static str = "thing";
        fn slot(&self) -> &Slot<Vec<u8>> {
            &self.0
        }
        fn from_slot(slot: Slot<Vec<u8>>) -> Self {
            Thing(slot)
        }
    }

    fn make() -> *mut Thing {
        let mut p = std::ptr::null_mut();
        // SAFETY: `p` is a local, writable pointer.
        unsafe { hand_out::<Thing>(vec![1, 2, 3], &mut p).unwrap() };
        p
    }

    #[test]
    fn readers_share_a_writer_is_alone() {
        let p = make();
        {
            let (a, b) = (get(p, "p").unwrap(), get(p, "p").unwrap());
            assert_eq!(a.len() + b.len(), 6);
            assert_eq!(get_mut(p, "p").err().unwrap().status, meshmove_status::Busy);
            assert_eq!(free(p, "p").unwrap_err().status, meshmove_status::Busy);
        }
        {
            let mut w = get_mut(p, "p").unwrap();
            w.push(4);
            assert_eq!(get(p, "p").err().unwrap().status, meshmove_status::Busy);
            assert_eq!(get_mut(p, "p").err().unwrap().status, meshmove_status::Busy);
        }
        assert_eq!(get(p, "p").unwrap().len(), 4);
        free(p, "p").unwrap();
        let e = get(p, "p").err().unwrap();
        assert_eq!(e.status, meshmove_status::InvalidHandle);
        assert!(e.msg.contains("already freed"), "{}", e.msg);
        assert_eq!(free(p, "p").unwrap_err().status, meshmove_status::InvalidHandle);
    }

    #[test]
    fn a_panic_poisons_the_handle_but_free_works() {
        let p = make();
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let mut w = get_mut(p, "p").unwrap();
            w.clear();
            panic!("half-changed");
        }));
        assert!(r.is_err());
        let e = get(p, "p").err().unwrap();
        assert!(e.msg.contains("PANIC"), "{}", e.msg);
        assert_eq!(get_mut(p, "p").err().unwrap().status, meshmove_status::InvalidHandle);
        free(p, "p").unwrap();
        assert!(get(p, "p").err().unwrap().msg.contains("already freed"));
    }
}
