//! The handles the library hands out, checked on every call that takes
//! one, so that a handle freed already, never handed out, of another kind,
//! null or misaligned is refused with a status and a message instead of
//! being read or freed a second time.
//!
//! A scene or result handle is not an address: it is a serial number,
//! never reused, shifted past a tag of its kind. The object lives in a
//! registry behind an [`Arc`], so a handle freed while another thread
//! still bakes with it stays alive until that call returns, and a stale
//! handle can never name a later object. Strings are real addresses (the
//! host reads them), kept in a registry of their own.

use crate::errors::Failure;
use std::collections::BTreeMap;
use std::ffi::{CString, c_char};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

/// Low bits of every handle, zero: a handle is aligned as any pointer is.
const ALIGN_BITS: u32 = 4;
/// Bits of the kind tag, above the alignment bits.
const TAG_BITS: u32 = 4;
/// The kinds of handle by tag (0 is never a tag, so 0 is never a handle).
const KINDS: [&str; 4] = ["", "scene", "result", "options"];
/// The tag of scene handles.
pub(crate) const SCENE: usize = 1;
/// The tag of result handles.
pub(crate) const RESULT: usize = 2;
/// The tag of options handles.
pub(crate) const OPTIONS: usize = 3;

/// The next serial number, shared by every kind so that no two handles
/// of any kinds are equal.
static NEXT_SERIAL: AtomicUsize = AtomicUsize::new(1);

/// The live objects of one kind, by handle.
pub(crate) struct Handles<T> {
    /// The index of the kind in [`KINDS`].
    tag: usize,
    live: Mutex<BTreeMap<usize, Arc<T>>>,
}

/// A mutex's contents even after a panic in another call (caught at the
/// boundary) poisoned it: the maps it guards are never left half-changed.
fn locked<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

impl<T> Handles<T> {
    /// An empty registry of the kind `KINDS[tag]`.
    pub(crate) const fn new(tag: usize) -> Self {
        Handles {
            tag,
            live: Mutex::new(BTreeMap::new()),
        }
    }

    fn kind(&self) -> &'static str {
        KINDS[self.tag]
    }

    /// Keeps `value` and returns its new handle.
    pub(crate) fn issue<H>(&self, value: T) -> Result<*mut H, Failure> {
        let serial = NEXT_SERIAL.fetch_add(1, Ordering::Relaxed);
        let handle = serial
            .checked_shl(TAG_BITS + ALIGN_BITS)
            .filter(|h| h >> (TAG_BITS + ALIGN_BITS) == serial)
            .map(|h| h | self.tag << ALIGN_BITS)
            .ok_or_else(|| Failure::argument(format!("no {} handles are left", self.kind())))?;
        locked(&self.live).insert(handle, Arc::new(value));
        Ok(std::ptr::without_provenance_mut(handle))
    }

    /// The live object of `handle`, named `what` in errors, or why not.
    pub(crate) fn get<H>(&self, handle: *const H, what: &str) -> Result<Arc<T>, Failure> {
        let address = handle.addr();
        if let Some(live) = locked(&self.live).get(&address) {
            return Ok(Arc::clone(live));
        }
        Err(Failure::argument(self.why_not(address, what)))
    }

    /// Frees the object of `handle` (named `what` in errors); null is
    /// allowed and frees nothing. Another thread still using the object
    /// keeps it until its call returns.
    pub(crate) fn free<H>(&self, handle: *mut H, what: &str) -> Result<(), Failure> {
        let address = handle.addr();
        if address == 0 {
            return Ok(());
        }
        match locked(&self.live).remove(&address) {
            Some(_) => Ok(()),
            None => Err(Failure::argument(self.why_not(address, what))),
        }
    }

    /// Why `address` is not a live handle of this kind.
    fn why_not(&self, address: usize, what: &str) -> String {
        let kind = self.kind();
        if address == 0 {
            return format!("{what} is null");
        }
        if !address.is_multiple_of(1 << ALIGN_BITS) {
            return format!(
                "{what} {address:#x} is misaligned: not a {kind} handle of this library"
            );
        }
        let serial = address >> (TAG_BITS + ALIGN_BITS);
        let tag = (address >> ALIGN_BITS) & ((1 << TAG_BITS) - 1);
        if serial == 0 || serial >= NEXT_SERIAL.load(Ordering::Relaxed) || tag == 0 {
            return format!("{what} {address:#x} is not a {kind} handle this library handed out");
        }
        match KINDS.get(tag) {
            Some(other) if tag != self.tag => {
                format!("{what} {address:#x} is a {other} handle, not a {kind}")
            }
            Some(_) => format!("{what} {address:#x} is a {kind} that was freed already"),
            None => format!("{what} {address:#x} is not a {kind} handle this library handed out"),
        }
    }
}

/// The strings the library handed out and the host has not freed, by
/// address.
static STRINGS: Mutex<BTreeMap<usize, CString>> = Mutex::new(BTreeMap::new());

/// `text` as a string the host owns until it calls
/// [`sssbake_string_free`](crate::sssbake_string_free).
pub(crate) fn issue_string(text: String) -> *mut c_char {
    let string = CString::new(text.replace('\0', " ")).unwrap_or_default();
    // The heap buffer does not move when the CString does.
    let pointer = string.as_ptr().cast_mut();
    locked(&STRINGS).insert(pointer.addr(), string);
    pointer
}

/// Frees a string [`issue_string`] handed out; null frees nothing.
pub(crate) fn free_string(string: *mut c_char) -> Result<(), Failure> {
    if string.is_null() {
        return Ok(());
    }
    match locked(&STRINGS).remove(&string.addr()) {
        Some(_) => Ok(()),
        None => Err(Failure::argument(format!(
            "string {:#x} is not a live string of this library: freed already, or never \
             handed out by sssbake_names or sssbake_bake_to_folder (a result's summary \
             belongs to its result)",
            string.addr()
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_handle_is_aligned_tagged_and_never_reused() {
        let numbers: Handles<u32> = Handles::new(SCENE);
        let words: Handles<&str> = Handles::new(RESULT);
        let one: *mut u8 = numbers.issue(7).ok().unwrap();
        let two: *mut u8 = numbers.issue(8).ok().unwrap();
        let word: *mut u8 = words.issue("x").ok().unwrap();
        assert_ne!(one, two);
        assert_eq!(one.addr() % 16, 0);
        assert_eq!(numbers.get(one, "n").ok().as_deref(), Some(&7));
        assert!(numbers.free(one, "n").is_ok());
        let again: *mut u8 = numbers.issue(9).ok().unwrap();
        assert_ne!(again, one, "a freed serial came back");
        let message = |r: Result<Arc<u32>, Failure>| r.err().map(|f| f.1).unwrap_or_default();
        assert!(message(numbers.get(one, "n")).ends_with("is a scene that was freed already"));
        assert!(message(numbers.get(word, "n")).ends_with("is a result handle, not a scene"));
        let after = std::ptr::without_provenance::<u8>(usize::MAX & !15);
        assert!(message(numbers.get(after, "n")).contains("not a scene handle this library"));
        let odd = std::ptr::without_provenance::<u8>(two.addr() + 1);
        assert!(message(numbers.get(odd, "n")).contains("misaligned"));
        assert!(numbers.free(one, "n").is_err(), "freed twice");
        assert!(numbers.free(std::ptr::null_mut::<u8>(), "n").is_ok());
    }
}
