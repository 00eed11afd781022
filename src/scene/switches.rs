//! The effects a stage can be asked to leave out, by name: a scene's
//! `[render] without = [...]` and the command line name them, and the
//! renderer asks whether each is off.

use serde::Deserialize;

/// Makes [`Switch`], [`Switch::ALL`] and [`Switch::name`] from one list,
/// so that a new switch is one line and cannot be left out of `ALL` (and
/// so of every name the parser, `raylab chapters` and the help know).
macro_rules! switches {
    ($($variant:ident $name:literal,)*) => {
        /// An effect a stage can be asked to leave out: one the renderer knows
        /// how to draw without (a stage without reflection shades as chapter 5
        /// did; without the tree it tests every object). A variant, not a string,
        /// so that a misspelt switch is a compile error rather than never off.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum Switch {
            $($variant,)*
        }

        impl Switch {
            /// Every switch, in chapter order (each at its own discriminant).
            pub const ALL: [Switch; [$(Switch::$variant),*].len()] = [$(Switch::$variant),*];

            /// Its name in scenes, on the command line and in `raylab chapters`.
            pub const fn name(self) -> &'static str {
                match self {
                    $(Switch::$variant => $name,)*
                }
            }
        }
    };
}

switches! {
    Planes "planes",
    Spheres "spheres",
    NearestHit "nearest-hit",
    Lighting "lighting",
    Phong "phong",
    Reflection "reflection",
    Antialiasing "antialiasing",
    Refraction "refraction",
    NestedMedia "nested-media",
    Triangles "triangles",
    SmoothShading "smooth-shading",
    Bvh "bvh",
    Implicit "implicit",
    PathTracing "path-tracing",
    NextEvent "next-event",
    Mis "mis",
    RussianRoulette "russian-roulette",
    LightTracing "light-tracing",
    Dispersion "dispersion",
}

/// A set of [`Switch`]es: the effects a stage is asked to leave out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SwitchedOff(u32);

impl SwitchedOff {
    /// Every effect that can be switched off, by name, in chapter order.
    pub const NAMES: [&'static str; Switch::ALL.len()] = {
        let mut names = [""; Switch::ALL.len()];
        let mut index = 0;
        while index < Switch::ALL.len() {
            names[index] = Switch::ALL[index].name();
            index += 1;
        }
        names
    };

    /// The set of the effects named, or the name that is not one.
    pub fn parse<'a>(names: impl IntoIterator<Item = &'a str>) -> Result<SwitchedOff, String> {
        let mut set = SwitchedOff::default();
        for name in names {
            let Some(index) = Self::NAMES.iter().position(|known| *known == name) else {
                return Err(format!(
                    "`{name}` is not an effect that can be switched off: {}",
                    Self::NAMES.join(", ")
                ));
            };
            set.0 |= 1 << index;
        }
        Ok(set)
    }

    /// The effects off in either set.
    pub fn union(self, other: SwitchedOff) -> SwitchedOff {
        SwitchedOff(self.0 | other.0)
    }

    /// Whether `switch` is off.
    pub fn contains(self, switch: Switch) -> bool {
        self.0 & (1 << switch as u32) != 0
    }

    /// The names of the effects off, in chapter order.
    pub fn names(self) -> Vec<&'static str> {
        Self::NAMES
            .iter()
            .enumerate()
            .filter(|(index, _)| self.0 & (1 << index) != 0)
            .map(|(_, name)| *name)
            .collect()
    }
}

impl<'de> Deserialize<'de> for SwitchedOff {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let names = Vec::<String>::deserialize(deserializer)?;
        SwitchedOff::parse(names.iter().map(String::as_str)).map_err(serde::de::Error::custom)
    }
}
