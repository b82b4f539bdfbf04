//! Status codes, the last error message of each thread, and the guard that
//! keeps panics on this side of the boundary.

use std::cell::RefCell;
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// What a call did.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SssbakeStatus {
    /// Done.
    Ok = 0,
    /// A null pointer, a length that does not match, a value out of range.
    InvalidArgument = 1,
    /// Input the bake cannot use: a broken mesh, an unknown object or
    /// preset, a material that is not physical.
    BadInput = 2,
    /// The cancel flag was raised.
    Cancelled = 3,
    /// A bug in the library (a caught panic); the message says where.
    Internal = 4,
    /// An output file or folder that cannot be written.
    CannotWrite = 5,
}

/// A failed call: its status and message.
pub(crate) struct Failure(pub SssbakeStatus, pub String);

impl Failure {
    pub(crate) fn argument(message: impl Into<String>) -> Self {
        Failure(SssbakeStatus::InvalidArgument, message.into())
    }

    pub(crate) fn input(message: impl Into<String>) -> Self {
        Failure(SssbakeStatus::BadInput, message.into())
    }
}

impl From<sssbake::Error> for Failure {
    fn from(error: sssbake::Error) -> Self {
        let status = match &error {
            sssbake::Error::Setting { .. } => SssbakeStatus::InvalidArgument,
            sssbake::Error::Input(_) => SssbakeStatus::BadInput,
            sssbake::Error::Output { .. } => SssbakeStatus::CannotWrite,
            sssbake::Error::Cancelled => SssbakeStatus::Cancelled,
        };
        // The limits as the settings struct calls them.
        let error = error.naming_limit(|field| match field {
            "max_memory" => "max_memory_bytes in SssbakeSettings".to_string(),
            other => format!("{other} in SssbakeSettings"),
        });
        Failure(status, error.to_string())
    }
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_error(message: &str) {
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = text);
}

/// The message of the last failed call on this thread (empty after a
/// success). Valid until the next call on this thread; do not free it.
#[unsafe(no_mangle)]
pub extern "C" fn sssbake_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// Runs `body`, turning its failure or panic into a status and message.
pub(crate) fn guarded(body: impl FnOnce() -> Result<(), Failure>) -> SssbakeStatus {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => {
            set_last_error("");
            SssbakeStatus::Ok
        }
        Ok(Err(Failure(status, message))) => {
            set_last_error(&message);
            status
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".into());
            set_last_error(&format!("internal error (please report): {what}"));
            SssbakeStatus::Internal
        }
    }
}

/// A C string argument as UTF-8, or why not.
///
/// # Safety
/// `text` is null or points to a NUL-terminated string.
pub(crate) unsafe fn text<'a>(text: *const c_char, what: &str) -> Result<&'a str, Failure> {
    if text.is_null() {
        return Err(Failure::argument(format!("{what} is null")));
    }
    // SAFETY: the caller passes a NUL-terminated string.
    unsafe { std::ffi::CStr::from_ptr(text) }
        .to_str()
        .map_err(|_| Failure::argument(format!("{what} is not UTF-8")))
}

/// A caller's array of `len` items, or why not (null with a nonzero length).
///
/// # Safety
/// `data` is null or points to `len` readable items.
pub(crate) unsafe fn slice<'a, T>(
    data: *const T,
    len: usize,
    what: &str,
) -> Result<&'a [T], Failure> {
    if len == 0 {
        return Ok(&[]);
    }
    if data.is_null() {
        return Err(Failure::argument(format!(
            "{what} is null but its length is {len}"
        )));
    }
    // A misaligned pointer would make the slice undefined behaviour.
    if !data
        .cast::<u8>()
        .addr()
        .is_multiple_of(std::mem::align_of::<T>())
    {
        return Err(Failure::argument(format!(
            "{what} is not aligned to {} bytes",
            std::mem::align_of::<T>()
        )));
    }
    // SAFETY: the caller passes `len` readable items.
    Ok(unsafe { std::slice::from_raw_parts(data, len) })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn last_error() -> String {
        // SAFETY: the library's own message, NUL-terminated.
        unsafe { std::ffi::CStr::from_ptr(sssbake_last_error()) }
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn a_panic_stops_at_the_boundary_as_an_internal_error_with_its_message() {
        let status = guarded(|| panic!("forced at {}", "the boundary"));
        assert_eq!(status, SssbakeStatus::Internal);
        assert_eq!(
            last_error(),
            "internal error (please report): forced at the boundary"
        );
        // The next call succeeds and clears the message.
        assert_eq!(guarded(|| Ok(())), SssbakeStatus::Ok);
        assert_eq!(last_error(), "");
    }

    #[test]
    fn misaligned_and_null_arrays_are_refused_before_a_slice_is_made() {
        let floats = [0.0f32; 4];
        let bytes: *const u8 = floats.as_ptr().cast();
        // SAFETY: one byte into a live array; never read, refused first.
        let off = unsafe { bytes.add(1) }.cast::<f32>();
        // SAFETY: refused before any read.
        let Err(error) = (unsafe { slice(off, 2, "positions") }) else {
            panic!("a misaligned array was accepted");
        };
        assert_eq!(error.0, SssbakeStatus::InvalidArgument);
        assert!(error.1.contains("not aligned to 4 bytes"), "{}", error.1);
        // SAFETY: null with a length is refused before any read.
        let Err(error) = (unsafe { slice(std::ptr::null::<f32>(), 3, "normals") }) else {
            panic!("a null array was accepted");
        };
        assert!(error.1.contains("normals is null but its length is 3"));
        // SAFETY: a live, aligned array of 4.
        let whole = unsafe { slice(floats.as_ptr(), 4, "uvs") };
        assert_eq!(whole.map(<[f32]>::len).ok(), Some(4));
    }
}
