//! Chapter 12's implicit surfaces as a scene file gives them: a tree of
//! nodes by name (`implicit = { torus = { ... } }`), turned into the
//! [`Sdf`] the renderer marches.

use serde::Deserialize;

use crate::Vec3;
use crate::number;
use crate::shapes::Sdf;

/// `implicit = { torus = { center = [..], major = .., minor = .. } }`: a
/// node of an implicit surface's tree, by name (chapter 12).
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum SdfSpec {
    Sphere {
        #[serde(deserialize_with = "number::vec3")]
        center: Vec3,
        #[serde(deserialize_with = "number::f32")]
        radius: f32,
    },
    Box {
        #[serde(deserialize_with = "number::vec3")]
        center: Vec3,
        #[serde(deserialize_with = "number::vec3")]
        half_size: Vec3,
    },
    RoundBox {
        #[serde(deserialize_with = "number::vec3")]
        center: Vec3,
        #[serde(deserialize_with = "number::vec3")]
        half_size: Vec3,
        #[serde(deserialize_with = "number::f32")]
        radius: f32,
    },
    Torus {
        #[serde(deserialize_with = "number::vec3")]
        center: Vec3,
        #[serde(deserialize_with = "number::f32")]
        major: f32,
        #[serde(deserialize_with = "number::f32")]
        minor: f32,
    },
    Capsule {
        #[serde(deserialize_with = "number::vec3")]
        a: Vec3,
        #[serde(deserialize_with = "number::vec3")]
        b: Vec3,
        #[serde(deserialize_with = "number::f32")]
        radius: f32,
    },
    Plane {
        #[serde(deserialize_with = "number::vec3")]
        point: Vec3,
        #[serde(deserialize_with = "number::vec3")]
        normal: Vec3,
    },
    Union(Vec<SdfSpec>),
    Intersection(Vec<SdfSpec>),
    Difference {
        shape: Box<SdfSpec>,
        minus: Box<SdfSpec>,
    },
    SmoothUnion {
        #[serde(deserialize_with = "number::f32")]
        blend: f32,
        shapes: Vec<SdfSpec>,
    },
    Translate {
        #[serde(deserialize_with = "number::vec3")]
        offset: Vec3,
        shape: Box<SdfSpec>,
    },
    Rotate {
        #[serde(deserialize_with = "number::vec3")]
        degrees: Vec3,
        shape: Box<SdfSpec>,
    },
    Displace {
        #[serde(deserialize_with = "number::f32")]
        amplitude: f32,
        #[serde(deserialize_with = "number::f32")]
        frequency: f32,
        shape: Box<SdfSpec>,
    },
}

impl SdfSpec {
    /// The tree, or why not. A smooth union of more than two shapes blends
    /// them in order, pairwise.
    pub(super) fn tree(&self) -> Result<Sdf, String> {
        let boxed = |spec: &SdfSpec| spec.tree().map(Box::new);
        Ok(match self {
            SdfSpec::Sphere { center, radius } => Sdf::Sphere {
                center: *center,
                radius: *radius,
            },
            SdfSpec::Box { center, half_size } => Sdf::Box {
                center: *center,
                half_size: *half_size,
            },
            SdfSpec::RoundBox {
                center,
                half_size,
                radius,
            } => Sdf::RoundBox {
                center: *center,
                half_size: *half_size,
                radius: *radius,
            },
            SdfSpec::Torus {
                center,
                major,
                minor,
            } => Sdf::Torus {
                center: *center,
                major: *major,
                minor: *minor,
            },
            SdfSpec::Capsule { a, b, radius } => Sdf::Capsule {
                a: *a,
                b: *b,
                radius: *radius,
            },
            SdfSpec::Plane { point, normal } => Sdf::Plane {
                point: *point,
                normal: crate::unit_vector(*normal).ok_or_else(|| {
                    format!("plane.normal = {normal}: a plane's normal must be finite and not zero")
                })?,
            },
            SdfSpec::Union(shapes) => {
                Sdf::Union(shapes.iter().map(SdfSpec::tree).collect::<Result<_, _>>()?)
            }
            SdfSpec::Intersection(shapes) => {
                Sdf::Intersection(shapes.iter().map(SdfSpec::tree).collect::<Result<_, _>>()?)
            }
            SdfSpec::Difference { shape, minus } => Sdf::Difference(boxed(shape)?, boxed(minus)?),
            SdfSpec::SmoothUnion { blend, shapes } => {
                let mut trees = shapes.iter().map(SdfSpec::tree);
                let (Some(first), Some(second)) = (trees.next(), trees.next()) else {
                    return Err(format!(
                        "smooth_union has {} shapes: it blends at least two",
                        shapes.len()
                    ));
                };
                let mut blended = Sdf::SmoothUnion {
                    shapes: (Box::new(first?), Box::new(second?)),
                    blend: *blend,
                };
                for next in trees {
                    blended = Sdf::SmoothUnion {
                        shapes: (Box::new(blended), Box::new(next?)),
                        blend: *blend,
                    };
                }
                blended
            }
            SdfSpec::Translate { offset, shape } => Sdf::Translate {
                offset: *offset,
                shape: boxed(shape)?,
            },
            SdfSpec::Rotate { degrees, shape } => {
                let radians = *degrees * (std::f32::consts::PI / 180.0);
                Sdf::Rotate {
                    rotation: glam::Quat::from_euler(
                        glam::EulerRot::XYZ,
                        radians.x,
                        radians.y,
                        radians.z,
                    ),
                    shape: boxed(shape)?,
                }
            }
            SdfSpec::Displace {
                amplitude,
                frequency,
                shape,
            } => Sdf::Displace {
                amplitude: *amplitude,
                frequency: *frequency,
                shape: boxed(shape)?,
            },
        })
    }

    /// How many levels the tree of the spec has, counted without
    /// recursing deeper than the tree may be (a hostile file's depth costs
    /// nothing). A smooth union of n shapes is n - 1 levels of pairwise
    /// blends ([`SdfSpec::tree`]), so that one of 15,000 shapes is refused
    /// here, not built into a chain that overflows the stack.
    pub(super) fn depth_within(&self, limit: usize) -> Option<usize> {
        let levels = match self {
            SdfSpec::SmoothUnion { shapes, .. } => shapes.len().saturating_sub(1).max(1),
            _ => 1,
        };
        let limit = limit.checked_sub(levels)?;
        let children: Vec<&SdfSpec> = match self {
            SdfSpec::Sphere { .. }
            | SdfSpec::Box { .. }
            | SdfSpec::RoundBox { .. }
            | SdfSpec::Torus { .. }
            | SdfSpec::Capsule { .. }
            | SdfSpec::Plane { .. } => vec![],
            SdfSpec::Union(shapes) | SdfSpec::Intersection(shapes) => shapes.iter().collect(),
            SdfSpec::SmoothUnion { shapes, .. } => shapes.iter().collect(),
            SdfSpec::Difference { shape, minus } => vec![shape, minus],
            SdfSpec::Translate { shape, .. }
            | SdfSpec::Rotate { shape, .. }
            | SdfSpec::Displace { shape, .. } => vec![shape],
        };
        let mut deepest = 0;
        for child in children {
            deepest = deepest.max(child.depth_within(limit)?);
        }
        Some(deepest + levels)
    }
}
