//! geardyn command line: parse arguments, call the library, write outputs. No physics here.

mod cli;

fn main() -> std::process::ExitCode {
    let args = cli::parse();
    // Ctrl-C: remove the staged outputs not yet moved into place (a commit under way finishes
    // first), so that an interrupted run leaves no half-written folder or file.
    let _ = ctrlc::set_handler(|| {
        geardyn::report::remove_unfinished();
        eprintln!("\ninterrupted: unfinished outputs removed");
        std::process::exit(130);
    });
    match cli::run(args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", cli::error_text(&e));
            std::process::ExitCode::from(2)
        }
    }
}
