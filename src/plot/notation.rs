//! The paper's symbols in text meant for people (figures and reports): the ASCII names used in
//! code, CSV columns and the command line (`Omega`, `zeta`, `F_hat`, `um`) become Ω, ζ, F̂, µm.
//! Whole words only, so `zeta_ci95` or `omega_n_hz` (JSON keys, file names) stay as they are.

/// ASCII word and its symbol. F̂ is F with a combining circumflex (there is no precomposed
/// character); the PNG renderer places the mark above the letter (see `raster_text`).
const SYMBOLS: [(&str, &str); 18] = [
    ("Omega", "Ω"),
    ("Omega_h", "Ωₕ"),
    ("Omega_T", "Ω_T"),
    ("omega_n", "ωₙ"),
    ("zeta", "ζ"),
    ("F_hat", "F\u{302}"),
    ("F_m", "Fₘ"),
    ("F_ah", "Fₐₕ"),
    ("F_ah1", "Fₐₕ₁"),
    ("F_ah2", "Fₐₕ₂"),
    ("F_ah3", "Fₐₕ₃"),
    ("F_hat1", "F\u{302}₁"),
    ("um", "µm"),
    ("um2", "µm²"),
    ("sigma", "σ"),
    ("Delta", "Δ"),
    ("q_a", "qₐ"),
    ("q_m", "qₘ"),
];

/// `text` with every whole word of `SYMBOLS` replaced by its symbol. A word is a run of ASCII
/// letters, digits and underscores.
pub fn symbols(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 8);
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        match SYMBOLS.iter().find(|(w, _)| *w == word.as_str()) {
            Some((_, s)) => out.push_str(s),
            // "Ω_h", as the command line prints it, gets its subscript too.
            None if word == "_h" && out.ends_with('Ω') => out.push('ₕ'),
            None => out.push_str(word),
        }
        word.clear();
    };
    for c in text.chars() {
        if c.is_ascii_alphanumeric() || c == '_' {
            word.push(c);
        } else {
            flush(&mut word, &mut out);
            out.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::symbols;

    #[test]
    fn whole_words_become_symbols() {
        assert_eq!(
            symbols("F_hat = 2, zeta = 0.05, Omega_h 0.3, pp DTE (um)"),
            "F\u{302} = 2, ζ = 0.05, Ωₕ 0.3, pp DTE (µm)"
        );
        assert_eq!(symbols("omega_n = 1600 Hz"), "ωₙ = 1600 Hz");
        assert_eq!(symbols("(a) q_a, (b) q_m - q_a"), "(a) qₐ, (b) qₘ - qₐ");
        assert_eq!(symbols("Ω_h = 1, Ω_T, x_h"), "Ωₕ = 1, Ω_T, x_h");
        // Keys, file names and longer words are left alone.
        assert_eq!(
            symbols("zeta_ci95 omega_n_hz drum Omegas fig11"),
            "zeta_ci95 omega_n_hz drum Omegas fig11"
        );
        assert_eq!(symbols(""), "");
    }
}
