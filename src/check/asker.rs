//! What the judge asks through: a step of a check, how a question can go
//! unanswered, and the trait of whatever answers. Both the judge and the
//! answerers it drives (a student's process, [`super::remote`]) name these,
//! so they sit below both and neither has to reach into the other.

use super::protocol::{Reply, Request};

/// What the judge is doing when it asks: for the notice of a step that
/// takes long, and for the message of a process that ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Step {
    pub chapter: u8,
    pub function: String,
    pub case: String,
}

impl std::fmt::Display for Step {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            out,
            "chapter {}'s check ran {} ({})",
            self.chapter,
            self.function,
            crate::text::terminal_safe(&self.case)
        )
    }
}

/// How a request went unanswered.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Ended {
    /// The process ended while it answered: how ("exited with status 0",
    /// "was killed by signal 11").
    Died(String),
    /// The time limit passed; nothing more is asked.
    TimedOut,
    /// The binary does not answer raylab's questions, or answers another
    /// version of them; nothing more is asked.
    Refused(String),
}

/// Something that answers the judge's questions.
pub trait Asker {
    /// The reply to `request`, asked during `step`.
    fn ask(&mut self, request: &Request, step: &Step) -> Result<Reply, Ended>;

    /// From now on, past `deadline` a question ends as
    /// [`Ended::TimedOut`] (and the next one starts afresh). An asker
    /// with no time limit of its own ignores it.
    fn set_deadline(&mut self, _deadline: Option<std::time::Instant>) {}
}
