//! A graded class as the instructor reads it: the CSV, the Markdown
//! summary `raylab grade` prints and the self-contained HTML report with a
//! section per student. These only read a [`Class`] and its students; how
//! they were graded is none of their business.

use std::fmt::Write as _;
use std::path::Path;

use super::{Class, Outcome, Student};
use crate::chapters::LAST_CHAPTER;
use crate::diff::psnr_text;
use crate::grade::{Grade, GradeError, Graded, STYLE, html_escape, markdown_escape};

/// The HTML anchor of a student's section: from their name alone, so that
/// a job grading one student writes the same section as a run of the class.
fn anchor(name: &str) -> String {
    format!("student-{:016x}", crate::output::fnv1a64(name.bytes()))
}

/// Writes `student`'s section of the class report to `sections`.
pub(super) fn write_section(
    sections: &mut dyn std::io::Write,
    student: &Student,
) -> Result<(), GradeError> {
    let mut section = String::new();
    student_section_html(&mut section, student)?;
    sections
        .write_all(section.as_bytes())
        .map_err(GradeError::Staging)
}

/// A chapter's status in a student's grade: `pass`, `fail`, `missing` or
/// `unreadable`, with the grading if there is one, or the reason.
enum ChapterStatus<'a> {
    Graded(&'a Graded),
    Missing,
    Unreadable(&'a str),
}

fn chapter_status(grade: &Grade, chapter: u8) -> ChapterStatus<'_> {
    if let Some(graded) = grade.graded.iter().find(|g| g.chapter == chapter) {
        ChapterStatus::Graded(graded)
    } else if let Some(unreadable) = grade.unreadable.iter().find(|u| u.chapter == chapter) {
        ChapterStatus::Unreadable(&unreadable.reason)
    } else {
        ChapterStatus::Missing
    }
}

impl ChapterStatus<'_> {
    fn name(&self) -> &'static str {
        match self {
            ChapterStatus::Graded(g) if g.passes() => "pass",
            ChapterStatus::Graded(_) => "fail",
            ChapterStatus::Missing => "missing",
            ChapterStatus::Unreadable(_) => "unreadable",
        }
    }
}

impl Class {
    /// One row per student and chapter (per student with `--code`, chapter
    /// `all`): student, chapter, status, then the metrics of a comparison.
    pub fn csv(&self) -> String {
        let mut csv = String::from(
            "student,chapter,status,max,mean,rmse,psnr_db,pixels_over,percent_over,size,detail\n",
        );
        let mut row = |fields: &[String]| {
            let cells: Vec<String> = fields.iter().map(|f| csv_field(f)).collect();
            csv.push_str(&cells.join(","));
            csv.push('\n');
        };
        for student in &self.students {
            let name = student.name.clone();
            let blank = || vec![String::new(); 7];
            match &student.outcome {
                Outcome::Refused(why) => {
                    let mut fields = vec![name, "all".into(), "refused".into()];
                    fields.extend(blank());
                    fields.push(why.clone());
                    row(&fields);
                }
                Outcome::Code(run) => {
                    let mut fields = vec![name.clone(), "all".into(), run.status.name().into()];
                    fields.extend(blank());
                    fields.push(Student::code_summary(run));
                    row(&fields);
                    for scene in &run.scenes {
                        let mut fields = vec![
                            name.clone(),
                            format!("scene:{}", scene.name),
                            if scene.passed { "pass" } else { "fail" }.into(),
                        ];
                        match &scene.metrics {
                            Some(m) => fields.extend([
                                m.max.to_string(),
                                format!("{:.6}", m.mean),
                                format!("{:.6}", m.rmse),
                                psnr_text(m.psnr_db),
                                m.pixels_over.to_string(),
                                format!("{:.4}", m.percent_over()),
                                format!("{}x{}", m.width, m.height),
                            ]),
                            None => fields.extend(blank()),
                        }
                        fields.push(scene.detail.clone());
                        row(&fields);
                    }
                }
                Outcome::Renders(grade) => {
                    for chapter in 1..=LAST_CHAPTER {
                        let status = chapter_status(grade, chapter);
                        let mut fields =
                            vec![name.clone(), chapter.to_string(), status.name().into()];
                        match &status {
                            ChapterStatus::Graded(g) => {
                                let m = &g.comparison.metrics;
                                fields.extend([
                                    m.max.to_string(),
                                    format!("{:.6}", m.mean),
                                    format!("{:.6}", m.rmse),
                                    psnr_text(m.psnr_db),
                                    m.pixels_over.to_string(),
                                    format!("{:.4}", m.percent_over()),
                                    format!("{}x{}", m.width, m.height),
                                    g.reference_source.clone(),
                                ]);
                            }
                            ChapterStatus::Missing => {
                                fields.extend(blank());
                                fields.push(grade.missing_detail(chapter));
                            }
                            ChapterStatus::Unreadable(why) => {
                                fields.extend(blank());
                                fields.push((*why).to_string());
                            }
                        }
                        row(&fields);
                    }
                }
            }
        }
        csv
    }

    /// The Markdown summary printed by `raylab grade CLASS/`.
    pub fn markdown(&self, report: &Path, csv: &Path) -> String {
        let mut md = String::new();
        let _ = writeln!(
            md,
            "# raylab grade: {} (a class)\n",
            markdown_escape(&self.folder.display().to_string())
        );
        let code = self
            .students
            .iter()
            .any(|s| matches!(s.outcome, Outcome::Code(_)));
        if code {
            md.push_str("| student | result |\n|---|---|\n");
        } else {
            md.push_str("| student |");
            for chapter in 1..=LAST_CHAPTER {
                let _ = write!(md, " {chapter} |");
            }
            md.push_str(" result |\n|---|");
            for _ in 1..=LAST_CHAPTER {
                md.push_str("---|");
            }
            md.push_str("---|\n");
        }
        for student in &self.students {
            let _ = write!(md, "| {} |", markdown_escape(&student.name));
            if let Outcome::Renders(grade) = &student.outcome {
                for chapter in 1..=LAST_CHAPTER {
                    let status = chapter_status(grade, chapter).name();
                    let _ = write!(
                        md,
                        " {} |",
                        if status == "fail" { "**fail**" } else { status }
                    );
                }
            } else if !code {
                for _ in 1..=LAST_CHAPTER {
                    md.push_str(" |");
                }
            }
            let verdict = match &student.outcome {
                Outcome::Refused(why) => format!("refused: {}", markdown_escape(why)),
                _ => student.verdict(),
            };
            let _ = writeln!(md, " {verdict} |");
        }
        md.push('\n');
        if !self.ignored.is_empty() {
            md.push_str("Ignored:\n");
            for i in &self.ignored {
                let _ = writeln!(
                    md,
                    "- {}: {}",
                    markdown_escape(&i.name),
                    markdown_escape(&i.reason)
                );
            }
            md.push('\n');
        }
        if !self.similar.is_empty() {
            md.push_str("Similar code (token k-grams, winnowed; skeleton excluded):\n");
            for pair in &self.similar {
                let _ = writeln!(
                    md,
                    "- {}: {} and {}, {:.0}% alike",
                    pair.what(),
                    markdown_escape(&pair.first),
                    markdown_escape(&pair.second),
                    100.0 * pair.similarity
                );
            }
            md.push('\n');
        }
        let _ = writeln!(
            md,
            "**{} of {} students pass everything.** Report: {}; CSV: {}",
            self.passed(),
            self.students.len(),
            markdown_escape(&report.display().to_string()),
            markdown_escape(&csv.display().to_string())
        );
        md
    }

    /// The self-contained HTML report: an overview, then one section per
    /// student, then the similar code (long, side by side: the students'
    /// statuses are what an instructor reads first). Images are inlined only for the chapters that fail (the
    /// student's, the reference, the heatmap); a passing chapter is one row
    /// of figures, so that the report of a class of 30 at 640x480 stays a
    /// few megabytes instead of a few hundred.
    pub fn html(&self) -> Result<String, GradeError> {
        let mut h = self.html_head();
        for student in &self.students {
            student_section_html(&mut h, student)?;
        }
        self.html_similar(&mut h);
        h.push_str(HTML_TAIL);
        Ok(h)
    }

    /// The report of a class graded by [`grade_class`](super::grade_class)
    /// or [`grade_class_code`](super::grade_class_code), whose students'
    /// sections are in `sections` (what they wrote there, from its start),
    /// streamed into `out`.
    pub fn write_html(
        &self,
        out: &mut dyn std::io::Write,
        sections: &mut dyn std::io::Read,
    ) -> std::io::Result<()> {
        out.write_all(self.html_head().as_bytes())?;
        std::io::copy(sections, out)?;
        let mut similar = String::new();
        self.html_similar(&mut similar);
        out.write_all(similar.as_bytes())?;
        out.write_all(HTML_TAIL.as_bytes())
    }

    /// The report up to the students' sections: the overview.
    fn html_head(&self) -> String {
        let mut h = String::new();
        let title = format!("raylab grade: {} (a class)", self.folder.display());
        let _ = write!(
            h,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
            html_escape(&title),
            html_escape(&title)
        );
        let _ = writeln!(
            h,
            "<p class=\"verdict {}\"><strong>{} of {} students pass everything.</strong></p>",
            if self.all_pass() { "pass" } else { "fail" },
            self.passed(),
            self.students.len()
        );
        let code = self
            .students
            .iter()
            .any(|s| matches!(s.outcome, Outcome::Code(_)));
        if !code {
            let c = &self.criteria;
            let _ = writeln!(
                h,
                "<p>A pixel is <em>over</em> when one of its R, G, B values differs from the reference by more than {} levels (of 255); a chapter passes when {}.</p>",
                c.threshold,
                crate::grade::allowance_text(c)
            );
        }
        self.html_summary_table(&mut h, code);
        self.html_ignored(&mut h);
        if !self.similar.is_empty() {
            let _ = writeln!(
                h,
                "<p class=\"problems\"><a href=\"#{SIMILAR_ANCHOR}\">Similar code</a>: {} pairs, after the students' sections.</p>",
                self.similar.len()
            );
        }
        h
    }

    /// The pairs of similar chapter files (or whole `src/`), their shared
    /// passages side by side.
    fn html_similar(&self, h: &mut String) {
        if self.similar.is_empty() {
            return;
        }
        let _ = writeln!(
            h,
            "<section class=\"problems similar\" id=\"{SIMILAR_ANCHOR}\">\n<h2>Similar code</h2>\n<p>Pairs whose chapter file, or whose whole src/ (where no chapter file is alike), shares at least {:.0}% of its fingerprints with the other's (token {}-grams winnowed over windows of {}, names and literals ignored, the workspace skeleton excluded), as the files were before the build: read them before concluding anything.</p>",
            100.0 * crate::grade::similarity::REPORTED,
            crate::grade::similarity::K,
            crate::grade::similarity::WINDOW
        );
        for pair in &self.similar {
            let _ = writeln!(
                h,
                "<h3>{}: {} and {}, {:.0}% alike</h3>\n<table>\n<tr><th>{}</th><th>{}</th></tr>",
                capitalised(&pair.what()),
                html_escape(&pair.first),
                html_escape(&pair.second),
                100.0 * pair.similarity,
                html_escape(&pair.first),
                html_escape(&pair.second)
            );
            for (first, second) in &pair.passages {
                let _ = writeln!(
                    h,
                    "<tr><td><pre>{}\n{}</pre></td><td><pre>{}\n{}</pre></td></tr>",
                    html_escape(&passage_place(first)),
                    html_escape(&first.text),
                    html_escape(&passage_place(second)),
                    html_escape(&second.text)
                );
            }
            h.push_str("</table>\n");
        }
        h.push_str("</section>\n");
    }

    /// The overview: one row per student, with a column per chapter unless
    /// the class handed in code (`code`), linked to their sections.
    fn html_summary_table(&self, h: &mut String, code: bool) {
        h.push_str("<table class=\"summary\">\n<tr><th>student</th>");
        if !code {
            for chapter in 1..=LAST_CHAPTER {
                let _ = write!(h, "<th>{chapter}</th>");
            }
        }
        h.push_str("<th>result</th></tr>\n");
        for student in &self.students {
            let _ = write!(
                h,
                "<tr><td><a href=\"#{}\">{}</a></td>",
                anchor(&student.name),
                html_escape(&student.name)
            );
            if !code {
                for chapter in 1..=LAST_CHAPTER {
                    match &student.outcome {
                        Outcome::Renders(grade) => {
                            let status = chapter_status(grade, chapter).name();
                            let class = if status == "pass" { "pass" } else { "fail" };
                            let _ = write!(h, "<td class=\"{class}\">{status}</td>");
                        }
                        _ => h.push_str("<td></td>"),
                    }
                }
            }
            let _ = writeln!(
                h,
                "<td class=\"{}\">{}</td></tr>",
                if student.passes() { "pass" } else { "fail" },
                html_escape(&student.verdict())
            );
        }
        h.push_str("</table>\n");
    }

    /// The entries of the class folder that are not students, if any.
    fn html_ignored(&self, h: &mut String) {
        if !self.ignored.is_empty() {
            h.push_str("<section class=\"problems\">\n<p><strong>Ignored:</strong></p>\n<ul>\n");
            for i in &self.ignored {
                let _ = writeln!(
                    h,
                    "<li><code>{}</code>: {}</li>",
                    html_escape(&i.name),
                    html_escape(&i.reason)
                );
            }
            h.push_str("</ul>\n</section>\n");
        }
    }
}

/// The anchor of the similar code's section, which the overview links to.
const SIMILAR_ANCHOR: &str = "similar-code";

const HTML_TAIL: &str = "</body>\n</html>\n";

/// One student's section of the class report: why they were refused, their
/// code's check run, or their chapters.
pub(super) fn student_section_html(h: &mut String, student: &Student) -> Result<(), GradeError> {
    let _ = writeln!(
        h,
        "<section class=\"chapter {}\" id=\"{}\">\n<h2>{} <span class=\"badge\">{}</span></h2>",
        if student.passes() { "pass" } else { "fail" },
        anchor(&student.name),
        html_escape(&student.name),
        html_escape(&student.verdict())
    );
    match &student.outcome {
        Outcome::Refused(why) => {
            let _ = writeln!(h, "<p>{}</p>", html_escape(why));
        }
        Outcome::Code(run) => {
            // The build's exit status: the verdict is raylab's, whatever the
            // student's process exits with.
            let build = match run.exit_code {
                Some(0) => "built".to_string(),
                Some(code) => format!("build failed (exit status {code})"),
                None => "build stopped".to_string(),
            };
            let _ = writeln!(
                h,
                "<p>{}; judged by raylab: {}</p>\n<pre>{}</pre>",
                html_escape(&build),
                html_escape(run.status.name()),
                html_escape(&Student::code_summary(run))
            );
            if !run.scenes.is_empty() {
                h.push_str("<table>\n<tr><th>hidden scene</th><th>result</th><th>max</th><th>PSNR (dB)</th><th>pixels over</th><th>detail</th></tr>\n");
                for scene in &run.scenes {
                    let (max, psnr, over) = match &scene.metrics {
                        Some(m) => (
                            m.max.to_string(),
                            psnr_text(m.psnr_db),
                            format!("{} ({:.3}%)", m.pixels_over, m.percent_over()),
                        ),
                        None => Default::default(),
                    };
                    let result = if scene.passed { "pass" } else { "fail" };
                    let _ = writeln!(
                        h,
                        "<tr><td>{}</td><td class=\"{result}\">{result}</td><td>{max}</td><td>{psnr}</td><td>{over}</td><td>{}</td></tr>",
                        html_escape(&scene.name),
                        html_escape(&scene.detail)
                    );
                }
                h.push_str("</table>\n");
            }
        }
        Outcome::Renders(grade) => student_renders_html(h, grade)?,
    }
    h.push_str("</section>\n");
    Ok(())
}

/// One student's chapters in the class report.
fn student_renders_html(h: &mut String, grade: &Grade) -> Result<(), GradeError> {
    h.push_str("<table>\n<tr><th>chapter</th><th>result</th><th>size</th><th>max</th><th>PSNR (dB)</th><th>pixels over</th><th>detail</th></tr>\n");
    for chapter in 1..=LAST_CHAPTER {
        let status = chapter_status(grade, chapter);
        let name = status.name();
        let class = if name == "pass" { "pass" } else { "fail" };
        match &status {
            ChapterStatus::Graded(g) => {
                let m = &g.comparison.metrics;
                let _ = writeln!(
                    h,
                    "<tr><td>{chapter}</td><td class=\"{class}\">{name}</td><td>{}x{}</td><td>{}</td><td>{}</td><td>{} ({:.3}%)</td><td>{}</td></tr>",
                    m.width,
                    m.height,
                    m.max,
                    psnr_text(m.psnr_db),
                    m.pixels_over,
                    m.percent_over(),
                    html_escape(&format!("reference: {}", g.reference_source))
                );
            }
            ChapterStatus::Missing => {
                let _ = writeln!(
                    h,
                    "<tr><td>{chapter}</td><td class=\"{class}\">{name}</td><td colspan=\"5\">{}</td></tr>",
                    html_escape(&grade.missing_detail(chapter))
                );
            }
            ChapterStatus::Unreadable(why) => {
                let _ = writeln!(
                    h,
                    "<tr><td>{chapter}</td><td class=\"{class}\">{name}</td><td colspan=\"5\">{}</td></tr>",
                    html_escape(why)
                );
            }
        }
    }
    h.push_str("</table>\n");
    if !grade.ignored.is_empty() {
        h.push_str("<p>Ignored:</p>\n<ul>\n");
        for i in &grade.ignored {
            let _ = writeln!(
                h,
                "<li><code>{}</code>: {}</li>",
                html_escape(&i.name),
                html_escape(&i.reason)
            );
        }
        h.push_str("</ul>\n");
    }
    for g in grade
        .graded
        .iter()
        .filter(|g| !g.passes() && g.images.is_some())
    {
        let _ = writeln!(
            h,
            "<h3>Chapter {} <span class=\"badge\">FAIL</span></h3>",
            g.chapter
        );
        crate::grade::figures_html(h, g, "student")?;
    }
    Ok(())
}

/// One CSV field (RFC 4180): quoted when it holds a comma, a quote or a
/// line break. A field a spreadsheet would run as a formula (a student's
/// folder named `=HYPERLINK(...)`) is prefixed with `'`. Control
/// characters (an escape sequence in a student's output would drive the
/// terminal of whoever runs `cat grades.csv`) and bidirectional overrides
/// are written as escapes, line breaks kept.
pub(crate) fn csv_field(text: &str) -> String {
    let text = crate::text::terminal_safe(text);
    let text = if text.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        format!("'{text}")
    } else {
        text
    };
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text
    }
}

/// Where a shared passage is: `line 12` of the chapter's file, or
/// `src/answers/ch02.rs, line 12`.
fn passage_place(passage: &crate::grade::similarity::Passage) -> String {
    match &passage.file {
        Some(file) => format!(
            "{}, line {}",
            crate::text::terminal_safe(file),
            passage.line
        ),
        None => format!("line {}", passage.line),
    }
}

/// `text` with its first letter in upper case.
fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields_are_quoted_and_formulas_defused() {
        assert_eq!(csv_field("alice"), "alice");
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
        assert_eq!(csv_field("two\nlines"), "\"two\nlines\"");
        assert_eq!(csv_field("=1+1"), "'=1+1");
        assert_eq!(csv_field("-2"), "'-2");
        assert_eq!(csv_field("a\u{1b}]0;owned\u{7}"), "a\\u{1b}]0;owned\\u{7}");
        assert_eq!(csv_field("\u{202e}gnp"), "\\u{202e}gnp");
    }
}
