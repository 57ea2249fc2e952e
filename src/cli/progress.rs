//! Progress bars (indicatif) for commands that can run over a second: on stderr, and only when
//! stderr is a terminal, so that logs and pipes never see them.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;

/// A bar over `len` bytes of the input named `name`, or `None` without a terminal or a length.
pub fn bytes(len: Option<u64>, name: &str) -> Option<ProgressBar> {
    let len = len?;
    bar(
        len,
        "{prefix} {bar:40} {bytes}/{total_bytes} {bytes_per_sec} eta {eta}",
        name,
    )
}

/// A bar over `len` steps (runs, frames, …) of the work named `name`, or `None` without a
/// terminal.
pub fn steps(len: u64, name: &str) -> Option<ProgressBar> {
    bar(len, "{prefix} {bar:40} {pos}/{len} eta {eta}", name)
}

/// A spinner for work of unknown length named `name`, ticking on its own, or `None` without a
/// terminal.
pub fn spinner(name: &str) -> Option<ProgressBar> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let s = ProgressBar::new_spinner();
    s.set_message(name.to_string());
    s.enable_steady_tick(std::time::Duration::from_millis(120));
    Some(s)
}

fn bar(len: u64, template: &str, name: &str) -> Option<ProgressBar> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_prefix(name.to_string());
    Some(bar)
}

/// Prints a line on stderr without tearing the bar (when there is one).
pub fn eprint(bar: Option<&ProgressBar>, msg: &str) {
    match bar {
        Some(b) => b.suspend(|| eprintln!("{msg}")),
        None => eprintln!("{msg}"),
    }
}
