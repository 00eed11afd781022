//! `raylab new`: a student workspace.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use crate::chapters::CHAPTERS;

#[derive(Debug, Args)]
pub struct NewArgs {
    /// The folder to create; it must not exist, or be empty. Its name
    /// becomes the crate's.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Fill in raylab's reference solutions instead of `todo!()`: the answer
    /// key, for instructors.
    #[arg(long)]
    pub solutions: bool,
}

pub fn new(args: &NewArgs) -> Result<i32> {
    let package = crate::workspace::create(&args.dir, args.solutions)?;
    let shown = crate::text::terminal_safe(&args.dir.display().to_string());
    let functions: usize = CHAPTERS.iter().map(|info| info.functions.len()).sum();
    if args.solutions {
        println!(
            "Created {shown} (crate {package}) with raylab's reference solutions: the answer key."
        );
    } else {
        println!(
            "Created {shown} (crate {package}): {} chapters, {functions} functions to write, \
             in src/chapters/.",
            CHAPTERS.len()
        );
    }
    println!("Next:");
    println!("  cd {shown}");
    println!("  cargo run --release -- render --chapter 1");
    println!("  cargo run --release -- check --chapter 1");
    Ok(0)
}
