//! The wire between the judge and a student's process.
//!
//! The judge (raylab's own process: `raylab grade --code`, or in a
//! workspace the `check` that starts the chapters in a child) sends
//! [`Request`]s; the student's binary, started as `serve`, answers each
//! with one [`Reply`] and nothing else. A request carries only the inputs
//! of a call ([`super::question::Call`]); a reply only the raw answer. Every
//! expectation stays with the judge.
//!
//! Each message is a frame: its length as four little-endian bytes, then
//! the message in postcard (serde's compact binary form, exact for every
//! `f32`, NaN and infinities included). A frame longer than [`MAX_FRAME`]
//! is refused before it is read, so a student's process cannot make the
//! judge allocate without bound.
//!
//! The first request is always [`Request::Hello`], the first reply
//! [`Reply::Hello`]: both say which protocol and which raylab source they
//! were built from ([`SOURCE`], a hash of raylab's files), and the judge
//! asks nothing of a binary built from another, which gets a message
//! saying so instead of a verdict. Those two messages keep their place
//! and their fields in every version of raylab.

use std::io::{Read, Write};

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::panics::Panic;
use super::question::{Answer, Call};

/// The protocol's number: raised whenever a message changes.
pub const PROTOCOL: u32 = 1;

/// The hash of raylab's source this binary was built from (see build.rs).
pub const SOURCE: &str = env!("RAYLAB_SOURCE");

/// The largest frame read: an image of the reference size is 230 kB, the
/// largest case's samples a few megabytes.
pub const MAX_FRAME: usize = 64 << 20;

/// The most memory the elements of a frame's collections may decode to,
/// each charged its size in memory as it is decoded: an image of
/// [`MAX_FRAME`] bytes takes as much, a frame of empty names would take 24
/// times as much.
pub const MAX_DECODED: usize = 2 * MAX_FRAME;

/// Who is speaking: the first message each way.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Hello {
    pub protocol: u32,
    pub source: String,
    /// raylab's version, for the message when the two differ.
    pub version: String,
}

impl Hello {
    /// This binary's.
    pub fn ours() -> Hello {
        Hello {
            protocol: PROTOCOL,
            source: SOURCE.to_string(),
            version: env!("CARGO_PKG_VERSION").to_string(),
        }
    }
}

/// Where the camera of a chapter's image stands under `--fresh`: drawn
/// anew for every seed, so that no image rendered beforehand (the
/// lessons' references are public) can stand for the student's render.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct View {
    pub position: [f32; 3],
    pub look_at: [f32; 3],
}

impl View {
    /// `camera` moved to this view (its up and field of view kept).
    pub fn applied_to(&self, camera: &crate::scene::CameraSpec) -> crate::scene::CameraSpec {
        crate::scene::CameraSpec {
            position: Vec3::from_array(self.position),
            look_at: Vec3::from_array(self.look_at),
            ..*camera
        }
    }
}

/// What the judge asks.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Request {
    /// First, always.
    Hello(Hello),
    /// One case's call.
    Case(Call),
    /// Chapter `chapter`'s built-in scene at the reference size, every
    /// pixel in linear light, as `check` judges it (path-traced samples
    /// cut to the screen's white), seen from `view` where given
    /// (`--fresh`), else from the scene's own camera.
    Image { chapter: u8, view: Option<View> },
    /// A scene (TOML) rendered at `chapter`'s stage as `raylab render`
    /// renders it, seen from `view` where given (`--fresh`): its sRGB
    /// pixels.
    Render {
        scene: String,
        chapter: u8,
        view: Option<View>,
    },
}

/// What the student's process answers.
#[derive(Debug, Serialize, Deserialize)]
pub enum Reply {
    /// First, always. `comparison`: the chapters are one of raylab's
    /// comparison wrappers, which run raylab's answers on purpose.
    Hello { hello: Hello, comparison: bool },
    /// The answer to one request, with raylab's own answers that ran while
    /// it was worked out (see [`crate::answer_key`]): on the thread that
    /// answered (`used`), and on threads the chapters started
    /// (`escaped`).
    Answer {
        answer: Answered,
        used: Vec<String>,
        escaped: Vec<String>,
    },
}

/// The answer itself.
#[derive(Debug, Serialize, Deserialize)]
pub enum Answered {
    Case(Answer),
    /// An image in linear light, row by row.
    Pixels(Vec<Vec3>),
    /// An image in sRGB, three bytes a pixel, row by row.
    Rgb {
        width: u32,
        height: u32,
        rgb: Vec<u8>,
    },
    /// The chapters panicked (`todo!()` among them).
    Panicked(Panic),
    /// The request could not be worked out (a scene the stage refuses):
    /// a problem of the check, not of the chapters.
    Error(String),
}

/// The most bytes of each text a student's process sends that raylab
/// keeps: a panic's message and place, an error, a name of an answer it
/// ran, its hello. That text goes into the verdicts, and from them into
/// the report and the CSV; whole, it could carry anything the process
/// read there.
pub const MAX_SENT_TEXT: usize = 1000;

/// The most names of raylab's answers one reply may list (raylab has a few
/// dozen).
const MAX_SENT_NAMES: usize = 256;

/// `text` cut to at most [`MAX_SENT_TEXT`] bytes (at a character), saying
/// so when it is.
pub fn bounded_text(mut text: String) -> String {
    if text.len() <= MAX_SENT_TEXT {
        return text;
    }
    let whole = text.len();
    let mut end = MAX_SENT_TEXT;
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    text.truncate(end);
    text.push_str(&format!(" [... cut: {whole} bytes in all]"));
    text
}

/// `names` each cut to a bound, without repeats, at most
/// [`MAX_SENT_NAMES`] of them.
fn bounded_names(names: Vec<String>) -> Vec<String> {
    let mut kept: Vec<String> = Vec::new();
    for name in names.into_iter().map(bounded_text) {
        if kept.len() == MAX_SENT_NAMES {
            break;
        }
        if !kept.contains(&name) {
            kept.push(name);
        }
    }
    kept
}

impl Reply {
    /// The reply with every text in it cut to a bound (see
    /// [`MAX_SENT_TEXT`]), as the judge takes it from a student's process.
    pub fn bounded(self) -> Reply {
        let hello_of = |hello: Hello| Hello {
            protocol: hello.protocol,
            source: bounded_text(hello.source),
            version: bounded_text(hello.version),
        };
        match self {
            Reply::Hello { hello, comparison } => Reply::Hello {
                hello: hello_of(hello),
                comparison,
            },
            Reply::Answer {
                answer,
                used,
                escaped,
            } => Reply::Answer {
                answer: match answer {
                    Answered::Panicked(panic) => Answered::Panicked(Panic {
                        message: bounded_text(panic.message),
                        location: panic.location.map(bounded_text),
                        file: panic.file.map(bounded_text),
                    }),
                    Answered::Error(error) => Answered::Error(bounded_text(error)),
                    other => other,
                },
                used: bounded_names(used),
                escaped: bounded_names(escaped),
            },
        }
    }
}

/// Why a frame could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum ProtocolError {
    #[error("the other process closed the pipe")]
    Closed,
    #[error("a frame of {0} bytes, more than the {MAX_FRAME} allowed")]
    TooLarge(usize),
    #[error("the pipe failed: {0}")]
    Io(#[from] std::io::Error),
    #[error("a message that is not one of raylab's: {0}")]
    Garbled(String),
}

/// Writes `message` as one frame and flushes it.
pub fn write_frame<T: Serialize>(
    writer: &mut impl Write,
    message: &T,
) -> Result<(), ProtocolError> {
    let bytes =
        postcard::to_stdvec(message).map_err(|error| ProtocolError::Garbled(error.to_string()))?;
    if bytes.len() > MAX_FRAME {
        return Err(ProtocolError::TooLarge(bytes.len()));
    }
    let length = u32::try_from(bytes.len()).map_err(|_| ProtocolError::TooLarge(bytes.len()))?;
    writer.write_all(&length.to_le_bytes())?;
    writer.write_all(&bytes)?;
    writer.flush()?;
    Ok(())
}

/// Reads one frame and decodes it; [`ProtocolError::Closed`] at the end of
/// the stream before a frame begins.
pub fn read_frame<T: for<'de> Deserialize<'de>>(
    reader: &mut impl Read,
) -> Result<T, ProtocolError> {
    let mut length = [0u8; 4];
    match reader.read_exact(&mut length) {
        Ok(()) => {}
        Err(error) if error.kind() == std::io::ErrorKind::UnexpectedEof => {
            return Err(ProtocolError::Closed);
        }
        Err(error) => return Err(error.into()),
    }
    let length = u32::from_le_bytes(length) as usize;
    if length > MAX_FRAME {
        return Err(ProtocolError::TooLarge(length));
    }
    let mut bytes = vec![0u8; length];
    reader.read_exact(&mut bytes).map_err(|error| {
        if error.kind() == std::io::ErrorKind::UnexpectedEof {
            ProtocolError::Closed
        } else {
            error.into()
        }
    })?;
    // A frame is one message, whole: bytes left after it mean a frame
    // whose length was not its own (a reply written over another).
    let budget = super::decoded_budget::Budget::new(MAX_DECODED);
    let garbled = |error: postcard::Error| {
        ProtocolError::Garbled(if budget.spent() {
            format!(
                "a message that would decode to more memory than the {MAX_DECODED} bytes a reply may take"
            )
        } else {
            error.to_string()
        })
    };
    let mut decoder = postcard::Deserializer::from_bytes(&bytes);
    let message = T::deserialize(super::decoded_budget::Charged::new(&mut decoder, &budget))
        .map_err(garbled)?;
    match decoder.finalize().map_err(garbled)? {
        [] => Ok(message),
        rest => Err(ProtocolError::Garbled(format!(
            "{} bytes after the message in its frame",
            rest.len()
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame whose length covers more than its message is refused, not
    /// read for the message at its start.
    #[test]
    fn a_frame_with_bytes_after_its_message_is_garbled() {
        let mut one = Vec::new();
        write_frame(&mut one, &Hello::ours()).unwrap();
        let body = &one[4..];
        let mut padded = Vec::new();
        padded.extend_from_slice(&((body.len() + 3) as u32).to_le_bytes());
        padded.extend_from_slice(body);
        padded.extend_from_slice(&[1, 2, 3]);
        let read: Result<Hello, _> = read_frame(&mut padded.as_slice());
        assert!(
            matches!(read, Err(ProtocolError::Garbled(ref why)) if why.contains("3 bytes after")),
            "{read:?}"
        );
        let read: Result<Hello, _> = read_frame(&mut one.as_slice());
        assert!(read.is_ok(), "{read:?}");
    }

    /// A frame of empty names is a byte a name on the wire and 24 in
    /// memory: it is refused once its names would decode to more than
    /// [`MAX_DECODED`], before they are made.
    #[test]
    fn a_frame_that_decodes_to_more_memory_than_its_bytes_is_refused() {
        let frame = |names: usize| {
            let mut varint = Vec::new();
            let mut left = names;
            loop {
                let byte = (left & 0x7f) as u8;
                left >>= 7;
                if left == 0 {
                    varint.push(byte);
                    break;
                }
                varint.push(byte | 0x80);
            }
            // Reply::Answer { answer: Answered::Error(""), used: [""; names], escaped: [] }
            let mut body = vec![1u8, 4, 0];
            body.extend(varint);
            body.resize(body.len() + names, 0);
            body.push(0);
            let mut wire = (body.len() as u32).to_le_bytes().to_vec();
            wire.extend(body);
            wire
        };
        let few: Reply = read_frame(&mut frame(3).as_slice()).expect("three names");
        assert!(matches!(few, Reply::Answer { ref used, .. } if used.len() == 3));
        let names = MAX_DECODED / std::mem::size_of::<String>() + 1;
        assert!(names < MAX_FRAME);
        let read: Result<Reply, _> = read_frame(&mut frame(names).as_slice());
        assert!(
            matches!(read, Err(ProtocolError::Garbled(ref why)) if why.contains("more memory")),
            "{read:?}"
        );
        // An image as large as a frame holds is within the budget.
        let pixels = Reply::Answer {
            answer: Answered::Pixels(vec![Vec3::ONE; (MAX_FRAME - 64) / 12]),
            used: Vec::new(),
            escaped: Vec::new(),
        };
        let mut wire = Vec::new();
        write_frame(&mut wire, &pixels).expect("fits a frame");
        let read: Result<Reply, _> = read_frame(&mut wire.as_slice());
        assert!(read.is_ok(), "{:?}", read.err());
    }

    #[test]
    fn frames_carry_every_f32_exactly_and_refuse_giants() {
        let mut wire = Vec::new();
        let pixels = vec![Vec3::new(f32::NAN, f32::INFINITY, -0.0), Vec3::splat(0.1)];
        let reply = Reply::Answer {
            answer: Answered::Pixels(pixels.clone()),
            used: vec!["Sphere::intersect".into()],
            escaped: Vec::new(),
        };
        write_frame(&mut wire, &reply).unwrap();
        let read: Reply = read_frame(&mut wire.as_slice()).unwrap();
        let Reply::Answer {
            answer: Answered::Pixels(back),
            used,
            ..
        } = read
        else {
            panic!("another message: {read:?}");
        };
        assert_eq!(used, ["Sphere::intersect"]);
        for (got, sent) in back.iter().zip(&pixels) {
            for (a, b) in got.to_array().iter().zip(sent.to_array()) {
                assert_eq!(a.to_bits(), b.to_bits());
            }
        }
        let giant = (u32::MAX).to_le_bytes();
        assert!(matches!(
            read_frame::<Reply>(&mut giant.as_slice()),
            Err(ProtocolError::TooLarge(_))
        ));
        assert!(matches!(
            read_frame::<Reply>(&mut [].as_slice()),
            Err(ProtocolError::Closed)
        ));
        let garbage = [3u8, 0, 0, 0, 0xff, 0xff, 0xff];
        assert!(matches!(
            read_frame::<Reply>(&mut garbage.as_slice()),
            Err(ProtocolError::Garbled(_))
        ));
    }

    /// The hello of every version is read by every other: its place in
    /// the enums and its fields never move.
    #[test]
    fn the_hello_is_the_first_variant_with_fixed_fields() {
        let hello = Request::Hello(Hello {
            protocol: 7,
            source: "abc".into(),
            version: "9.9.9".into(),
        });
        let bytes = postcard::to_stdvec(&hello).unwrap();
        assert_eq!(
            bytes,
            [0, 7, 3, b'a', b'b', b'c', 5, b'9', b'.', b'9', b'.', b'9']
        );
        let reply = Reply::Hello {
            hello: Hello::ours(),
            comparison: false,
        };
        assert_eq!(postcard::to_stdvec(&reply).unwrap()[0], 0);
    }
}
