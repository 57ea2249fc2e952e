//! `lplace completions SHELL` and `lplace man`: the shell completion script and the man page,
//! generated from the same clap definitions as `--help` (so they cannot drift from it).

use super::args::{Cli, CompletionsArgs};
use super::{CliError, EXIT_OK};
use clap::CommandFactory;
use std::io::Write;

/// Prints the completion script for the shell asked for.
pub fn completions(args: &CompletionsArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let mut cmd = Cli::command();
    // Generation panics on nothing we pass; it writes into a buffer so that a closed stdout
    // surfaces as our own write error.
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut cmd, "lplace", &mut script);
    out.write_all(&script)?;
    Ok(EXIT_OK)
}

/// Prints the man page of `lplace` (roff) with a section per subcommand.
pub fn man(out: &mut impl Write) -> Result<u8, CliError> {
    let cmd = Cli::command();
    let mut page = Vec::new();
    let man = clap_mangen::Man::new(cmd.clone());
    man.render_title(&mut page)?;
    man.render_name_section(&mut page)?;
    man.render_synopsis_section(&mut page)?;
    man.render_description_section(&mut page)?;
    man.render_options_section(&mut page)?;
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        writeln!(page, ".SH \"LPLACE {}\"", sub.get_name().to_uppercase())?;
        let sub = sub.clone().bin_name(format!("lplace {}", sub.get_name()));
        let sub_man = clap_mangen::Man::new(sub);
        sub_man.render_description_section(&mut page)?;
        sub_man.render_synopsis_section(&mut page)?;
        sub_man.render_options_section(&mut page)?;
    }
    man.render_version_section(&mut page)?;
    out.write_all(&page)?;
    Ok(EXIT_OK)
}
