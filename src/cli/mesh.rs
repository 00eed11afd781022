//! `raylab mesh`: write a closed test model as an OBJ file.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use crate::mesh::{MAX_GENERATED_TRIANGLES, MAX_MESH_TRIANGLES};

/// Write a closed triangle model of about N triangles as an OBJ file.
///
/// The model is a lumpy torus of radius 1 around the Y axis (tube radius
/// about 0.4), closed (every edge between exactly two triangles), wound
/// counter-clockwise seen from outside, with smooth vertex normals. It
/// depends on N only: the same N gives the same bytes on every machine.
/// The count written is at least N and close to it
/// (1,000 gives 1,008; 1,000,000 gives 1,000,386; at least 18).
///
/// A scene places it with `mesh = { obj = "OUT.obj", ... }`; scenes load
/// models of at most 4,000,000 triangles.
///
/// Exit status: 0 written, 2 error (N out of range, an output that cannot
/// be written; nothing is written then).
#[derive(Debug, Args)]
#[command(long_about)]
pub struct MeshArgs {
    /// About how many triangles: a whole number from 1 to 16000000.
    #[arg(long, value_name = "N", value_parser = parse_triangles, allow_hyphen_values = true)]
    pub triangles: usize,
    /// Where to write the model (a name ending in .obj). An existing file
    /// is replaced only if raylab wrote it and it is writable; anything
    /// else needs --force.
    #[arg(short, long, value_name = "OUT.obj")]
    pub output: PathBuf,
    /// Replace the output even if raylab did not write it or it is
    /// read-only (it keeps its permissions).
    #[arg(long)]
    pub force: bool,
}

fn parse_triangles(text: &str) -> Result<usize, String> {
    super::whole_number(
        text,
        MAX_GENERATED_TRIANGLES as u64,
        "the number of triangles must be",
    )
    .map(|n| n as usize)
}

pub fn mesh(args: &MeshArgs) -> Result<i32> {
    // Checked before the model is built: a large one takes seconds.
    crate::mesh::check_obj_output("-o", &args.output, args.force)?;
    let mesh = crate::mesh::generate_closed_mesh(args.triangles)?;
    crate::mesh::write_obj_file(&args.output, &mesh)?;
    let path = crate::text::terminal_safe(&args.output.display().to_string());
    println!(
        "{} triangles, {} vertices: {path}",
        mesh.triangles.len(),
        mesh.positions.len()
    );
    if mesh.triangles.len() > MAX_MESH_TRIANGLES {
        println!(
            "note: a scene loads models of at most {MAX_MESH_TRIANGLES} triangles; this one is for \
             other uses"
        );
    }
    Ok(0)
}
