//! What the programs echo of their input, made safe for a terminal.

/// A message about the input (a bad line echoed, a block's bytes) with
/// each control character escaped (`\u{1b}`, `\u{0}`, `\t`): a hostile log's
/// escape sequences, bells and NULs never reach the terminal as they are.
pub(crate) struct Printable<'a>(pub(crate) &'a dyn std::fmt::Display);

impl std::fmt::Display for Printable<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        struct Escaping<'a, 'b>(&'a mut std::fmt::Formatter<'b>);
        impl std::fmt::Write for Escaping<'_, '_> {
            fn write_str(&mut self, s: &str) -> std::fmt::Result {
                for c in s.chars() {
                    if c.is_control() {
                        write!(self.0, "{}", c.escape_default())?;
                    } else {
                        std::fmt::Write::write_char(self.0, c)?;
                    }
                }
                Ok(())
            }
        }
        std::fmt::Write::write_fmt(&mut Escaping(f), format_args!("{}", self.0))
    }
}
