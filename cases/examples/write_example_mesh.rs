//! Writes docs/examples/channel.msh (the cylinder in a channel at h = 1/4) for the CLI example;
//! the physical names are added by the caller (see docs/examples/README.md).
fn main() {
    let m = meshmove_cases::meshes::cylinder_channel(0.25);
    meshmove::io::write_msh22(&m, std::path::Path::new("docs/examples/channel.msh")).unwrap();
}
