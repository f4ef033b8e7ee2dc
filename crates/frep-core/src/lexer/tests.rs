//! Tests of the lexer: tokens, numbers with the reference's arithmetic, and
//! errors.

use super::*;

fn kinds(src: &str) -> Vec<TokenKind> {
    let mut lx = Lexer::new(src);
    let mut out = Vec::new();
    loop {
        let t = lx.next_token();
        if t.kind == TokenKind::Eof {
            return out;
        }
        out.push(t.kind);
    }
}

fn num(src: &str) -> f64 {
    match kinds(src).as_slice() {
        [TokenKind::Num(v)] => *v,
        other => panic!("{src}: {other:?}"),
    }
}

#[test]
fn numbers_match_reference_arithmetic() {
    // The reference prints these with %.17g (SPEC §1, §7).
    let exact = |printed: &str| printed.parse::<f64>().unwrap_or(f64::NAN).to_bits();
    assert_eq!(num("2.5E+2").to_bits(), exact("250.00000000000011"));
    assert_ne!(num("2.5E+2"), 250.0);
    assert_eq!(num("0.1e-3").to_bits(), exact("9.9999999999999937e-05"));
    assert_eq!(num("42"), 42.0);
    assert_eq!(num(".5"), 0.5);
    assert_eq!(num("3."), 3.0);
    assert_eq!(num("1.e1").to_bits(), exact("10.000000000000002")); // exp(1 * ln 10), as the reference
                                                                    // Fraction digits are accumulated as d/10^k (not parsed exactly).
    assert_eq!(num("0.3"), 0.3);
    assert_eq!(
        num("1.0472"),
        1.0 + 0.0 / 10.0 + 4.0 / 100.0 + 7.0 / 1000.0 + 2.0 / 10000.0
    );
}

#[test]
fn reference_exponent_quirk_is_replicated() {
    // The reference reads the exponent `-12` as -1*10+2 = -8.
    assert_eq!(num("1e-12"), (-8.0 * std::f64::consts::LN_10).exp());
    assert_eq!(num("1e-10"), (-10.0 * std::f64::consts::LN_10).exp());
    assert_eq!(num("1e12"), (12.0 * std::f64::consts::LN_10).exp());
}

#[test]
fn lenient_leading_zeros() {
    assert_eq!(num("01"), 1.0);
    assert_eq!(num("007.5"), 7.5);
    assert_eq!(num("1e0"), 1.0);
    assert_eq!(num("1e05"), num("1e5"));
    assert_eq!(num("1e-05"), num("1e-5"));
    assert_eq!(num("2E+000"), 2.0);
}

#[test]
fn words_and_keywords() {
    use TokenKind::*;
    assert_eq!(
        kinds("My_Model X A s ARRAY If tHeN else EndIf while LOOP endloop and OR not xor hfSphere"),
        vec![
            Ident("my_model".into()),
            X,
            A,
            S,
            Array,
            If,
            Then,
            Else,
            EndIf,
            While,
            Loop,
            EndLoop,
            And,
            Or,
            Not,
            Xor,
            Ident("hfsphere".into())
        ]
    );
}

#[test]
fn punctuation_and_comments() {
    use TokenKind::*;
    assert_eq!(
        kinds("^+-~/*&|\\@,;=()[]{}< <= > >= /= -- comment ( \r\n-x--end"),
        vec![
            Caret, Plus, Minus, Tilde, Slash, Star, Amp, Pipe, Backslash, At, Comma, Semi, Assign,
            LParen, RParen, LBracket, RBracket, LBrace, RBrace, Lt, Le, Gt, Ge, Ne, Minus, X
        ]
    );
}

#[test]
fn positions_are_in_characters() {
    let mut lx = Lexer::new("-- é\n\t é");
    let t = lx.next_token();
    assert_eq!((t.span.line, t.span.col), (2, 3));
    match t.kind {
        TokenKind::Error(d) => {
            assert!(d.message.contains("unknown character `é`"), "{}", d.message);
            assert_eq!((d.span.line, d.span.col), (2, 3));
        }
        k => panic!("{k:?}"),
    }
    assert_eq!(lx.next_token().kind, TokenKind::Eof);
}

#[test]
fn strings() {
    assert_eq!(kinds("\"ab c\""), vec![TokenKind::Str("ab c".into())]);
    match &kinds("\"abc\nx")[..] {
        [TokenKind::Error(d)] => assert_eq!(d.message, "unterminated string"),
        k => panic!("{k:?}"),
    }
}

#[test]
fn malformed_numbers() {
    for src in [".", "1e", "1e+", ".e5", "2E-x"] {
        match &kinds(src)[..] {
            [TokenKind::Error(d), ..] => {
                assert!(d.message.contains("malformed number"), "{src}: {d:?}")
            }
            k => panic!("{src}: {k:?}"),
        }
    }
}
