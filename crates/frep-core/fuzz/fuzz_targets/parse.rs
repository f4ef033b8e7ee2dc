//! Fuzz target: the lexer and parser must never panic, overflow the stack or
//! hang, whatever UTF-8 text they are given; diagnostics must render.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(source) = std::str::from_utf8(data) else {
        return;
    };
    match frep_core::parse(source) {
        Ok(program) => assert!(!program.bodies.is_empty()),
        Err(d) => {
            assert!(d.span.line >= 1 && d.span.col >= 1);
            assert!(d.span.start <= d.span.end && d.span.end <= source.len());
            assert!(source.is_char_boundary(d.span.start) && source.is_char_boundary(d.span.end));
            let _ = d.render(source, Some("fuzz.hf"));
        }
    }
});
