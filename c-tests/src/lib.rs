//! The C header's functions, found by name in the harness the build script compiled with the
//! system C compiler (`sqt_find`), for the tests in `tests/header.rs` to call and hold to the
//! runtime's bits.

use core::ffi::c_char;

extern "C" {
    fn sqt_find(name: *const c_char) -> Option<unsafe extern "C" fn()>;
    fn sqt_function_count() -> usize;
    fn sqt_function_name(i: usize) -> *const c_char;
    fn sqt_q63(name: *const c_char) -> *const u64;
}

/// The header's function `name` (`sq_...`), as an untyped pointer: the caller transmutes it to
/// the function's C signature. Panics where the header has no such function.
pub fn find(name: &str) -> unsafe extern "C" fn() {
    let mut c = Vec::with_capacity(name.len() + 1);
    c.extend_from_slice(name.as_bytes());
    c.push(0);
    // SAFETY: `c` is a NUL-terminated string that outlives the call; sqt_find only reads it.
    unsafe { sqt_find(c.as_ptr().cast()) }
        .unwrap_or_else(|| panic!("the C header has no function {name}"))
}

/// The names of the functions the header defines, in its order.
pub fn function_names() -> Vec<String> {
    // SAFETY: no arguments, returns a constant.
    let n = unsafe { sqt_function_count() };
    (0..n)
        .map(|i| {
            // SAFETY: i < n, so the harness returns one of its static NUL-terminated names.
            let p = unsafe { sqt_function_name(i) };
            // SAFETY: as above, a valid C string for the program's life.
            unsafe { core::ffi::CStr::from_ptr(p) }
                .to_string_lossy()
                .into_owned()
        })
        .collect()
}

/// The header's 8-bit curve `name` on the 2⁶³ scale (`sq_srgb8_q63`, say: 256 entries), for the
/// functions of sets made at run time; `None` where the header has no such table.
pub fn q63(name: &str) -> Option<*const u64> {
    let mut c = Vec::with_capacity(name.len() + 1);
    c.extend_from_slice(name.as_bytes());
    c.push(0);
    // SAFETY: `c` is a NUL-terminated string that outlives the call; sqt_q63 only reads it and
    // returns a pointer to one of the header's static tables, or NULL.
    let p = unsafe { sqt_q63(c.as_ptr().cast()) };
    (!p.is_null()).then_some(p)
}
