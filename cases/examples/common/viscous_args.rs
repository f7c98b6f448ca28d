//! The viscous probes' first arguments (included by path): the mesh's kind and size, the motion.

use meshmove_cases::viscous::BodyMotion;

/// The kind (default `spheroid`), size (default `8`) and motion (`plunge`, else the pitch) in
/// `args`' first three places.
pub fn kind_size_motion(args: &[String]) -> (&str, &str, BodyMotion) {
    let kind = args.first().map_or("spheroid", |s| s.as_str());
    let size = args.get(1).map_or("8", |s| s.as_str());
    let m = match args.get(2).map(|s| s.as_str()) {
        Some("plunge") => BodyMotion::Plunge,
        _ => BodyMotion::Pitch,
    };
    (kind, size, m)
}
