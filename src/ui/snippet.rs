//! Source excerpts for snippets that the plain rendering would make unreadable or unsafe:
//! lines longer than `MAX_LINE_CHARS` are cut around the labels (with `…`, as rustc
//! does), control and bidi characters are escaped (`escape.rs`), and a label spanning
//! more than `MAX_LABEL_LINES` lines is shown on its first line only. An excerpt is a
//! small source holding only the labelled lines; it implements codespan's `Files` so that
//! line and column numbers are still those of the real file.

use super::escape::{needs_escape, push_safe};
use codespan_reporting::files::{Error, Files};
use mapc_frontend::SourceFile;
use std::collections::BTreeSet;
use std::ops::Range;

/// A labelled line longer than this (in characters) is cut around its labels.
pub const MAX_LINE_CHARS: usize = 160;
/// Characters kept before the first label of a cut line.
const CONTEXT_CHARS: usize = 40;
/// A label over more lines than this is shown on its first line only.
pub const MAX_LABEL_LINES: usize = 4;

/// The line starts of each source, computed once per report.
pub struct SourceLines<'a> {
    files: Vec<(&'a str, &'a str, Vec<usize>)>,
}

impl<'a> SourceLines<'a> {
    pub fn new(sources: &'a [SourceFile]) -> Self {
        let files = sources
            .iter()
            .map(|s| {
                let text = s.text.as_str();
                let starts = std::iter::once(0)
                    .chain(text.match_indices('\n').map(|(i, _)| i + 1))
                    .collect();
                (s.name.as_str(), text, starts)
            })
            .collect();
        SourceLines { files }
    }

    fn line_of(&self, file: usize, byte: usize) -> usize {
        let starts = &self.files[file].2;
        starts.partition_point(|&s| s <= byte).saturating_sub(1)
    }

    /// Line `l` of `file` without its line break.
    fn line(&self, file: usize, l: usize) -> (usize, &'a str) {
        let (_, text, starts) = &self.files[file];
        let start = starts[l];
        let end = starts.get(l + 1).copied().unwrap_or(text.len());
        let line = &text[start..end];
        (start, line.trim_end_matches(['\n', '\r']))
    }

    /// Clamps `r` into `file` on character boundaries (start ≤ end).
    fn clamp(&self, file: usize, r: &Range<usize>) -> Range<usize> {
        let text = self.files[file].1;
        let mut end = r.end.min(text.len());
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        let mut start = r.start.min(end);
        while !text.is_char_boundary(start) {
            start -= 1;
        }
        start..end
    }

    /// The last line a label covers (an empty label: its own line).
    fn end_line(&self, file: usize, r: &Range<usize>) -> usize {
        self.line_of(file, r.end.saturating_sub(1).max(r.start))
    }

    /// Would the plain rendering of these labels print a long line, a control or bidi
    /// character, or a label over many lines? It prints the labelled lines and a single
    /// line between two of them, so all of those are looked at.
    pub fn needs_excerpt(&self, labels: &[(usize, Range<usize>)]) -> bool {
        let mut shown: BTreeSet<(usize, usize)> = BTreeSet::new();
        for (file, r) in labels {
            let r = self.clamp(*file, r);
            let (first, last) = (self.line_of(*file, r.start), self.end_line(*file, &r));
            if last - first + 1 > MAX_LABEL_LINES {
                return true;
            }
            shown.extend((first..=last).map(|l| (*file, l)));
        }
        let between: Vec<(usize, usize)> = shown
            .iter()
            .zip(shown.iter().skip(1))
            .filter(|(a, b)| a.0 == b.0 && b.1 == a.1 + 2)
            .map(|(a, _)| (a.0, a.1 + 1))
            .collect();
        shown.extend(between);
        shown.iter().any(|&(file, l)| {
            let line = self.line(file, l).1;
            line.len() > MAX_LINE_CHARS && line.chars().count() > MAX_LINE_CHARS
                || line.chars().any(needs_escape)
        })
    }
}

/// One file's excerpt: its labelled lines, cut and escaped.
struct Excerpt<'a> {
    name: &'a str,
    text: String,
    /// Start of each excerpt line in `text`, plus `text.len()`.
    starts: Vec<usize>,
    /// The real line number of each excerpt line.
    numbers: Vec<usize>,
    /// Per excerpt line: (byte in `text`, real 1-based column) of each character, and
    /// of the line end.
    columns: Vec<Vec<(usize, usize)>>,
}

/// Excerpts of the files some labels point into, indexed by file id.
pub struct Excerpts<'a> {
    files: Vec<Option<Excerpt<'a>>>,
}

impl<'a> Excerpts<'a> {
    /// The excerpts for `labels` (file id, byte range) and the labels' ranges in them.
    pub fn new(
        lines: &SourceLines<'a>,
        labels: &[(usize, Range<usize>)],
    ) -> (Self, Vec<Range<usize>>) {
        let mut files: Vec<Option<Excerpt>> = (0..lines.files.len()).map(|_| None).collect();
        let mut ranges = vec![0..0; labels.len()];
        // Labels clamped to their files and to MAX_LABEL_LINES.
        let clamped: Vec<Range<usize>> = labels
            .iter()
            .map(|(file, r)| {
                let r = lines.clamp(*file, r);
                let first = lines.line_of(*file, r.start);
                if lines.end_line(*file, &r) - first + 1 > MAX_LABEL_LINES {
                    let (start, line) = lines.line(*file, first);
                    r.start..(start + line.len()).max(r.start)
                } else {
                    r
                }
            })
            .collect();
        for (file, slot) in files.iter_mut().enumerate() {
            let mine: Vec<usize> = (0..labels.len()).filter(|&i| labels[i].0 == file).collect();
            if mine.is_empty() {
                continue;
            }
            let mut needed: BTreeSet<usize> = BTreeSet::new();
            for &i in &mine {
                let r = &clamped[i];
                needed.extend(lines.line_of(file, r.start)..=lines.end_line(file, r));
            }
            // A single line between two labelled lines is shown, as the plain rendering does.
            let gaps: Vec<usize> = needed
                .iter()
                .zip(needed.iter().skip(1))
                .filter(|(a, b)| **b == **a + 2)
                .map(|(a, _)| a + 1)
                .collect();
            needed.extend(gaps);
            let mut ex = Excerpt {
                name: lines.files[file].0,
                text: String::new(),
                starts: Vec::new(),
                numbers: Vec::new(),
                columns: Vec::new(),
            };
            let mut prev: Option<usize> = None;
            for &l in &needed {
                if prev.is_some_and(|p| l > p + 2) {
                    // Two empty lines: the renderer shows a break (`·`) for the gap.
                    for n in [l - 2, l - 1] {
                        ex.starts.push(ex.text.len());
                        ex.numbers.push(n + 1);
                        ex.columns.push(vec![(ex.text.len(), 1)]);
                        ex.text.push('\n');
                    }
                }
                prev = Some(l);
                let (line_start, line) = lines.line(file, l);
                // The labels' ends on this line, as byte offsets into the line.
                let mut marks: Vec<usize> = Vec::new();
                for &i in &mine {
                    for b in [clamped[i].start, clamped[i].end] {
                        if (line_start..=line_start + line.len()).contains(&b) {
                            marks.push(b - line_start);
                        }
                    }
                }
                let window = window(line, &marks);
                ex.starts.push(ex.text.len());
                ex.numbers.push(l + 1);
                let mut cols = Vec::new();
                if window.start > 0 {
                    ex.text.push('…');
                }
                let mut col = line[..window.start].chars().count() + 1;
                // Real byte offset -> excerpt byte offset, for the labels.
                let mut map: Vec<(usize, usize)> = Vec::new();
                for (b, c) in line[window.clone()].char_indices() {
                    let real = line_start + window.start + b;
                    map.push((real, ex.text.len()));
                    cols.push((ex.text.len(), col));
                    push_safe(&mut ex.text, c);
                    col += 1;
                }
                map.push((line_start + window.end, ex.text.len()));
                cols.push((ex.text.len(), col));
                if window.end < line.len() {
                    ex.text.push('…');
                }
                ex.text.push('\n');
                ex.columns.push(cols);
                // Labels: an offset before the window maps to its start, after it to its end.
                let (first, last) = (map[0], map[map.len() - 1]);
                let to_excerpt = |real: usize| {
                    if real <= first.0 {
                        first.1
                    } else if real >= last.0 {
                        last.1
                    } else {
                        let k = map.partition_point(|m| m.0 < real);
                        map[k].1
                    }
                };
                for &i in &mine {
                    let r = &clamped[i];
                    if lines.line_of(file, r.start) == l {
                        ranges[i].start = to_excerpt(r.start);
                        ranges[i].end = ranges[i].start;
                    }
                    if lines.end_line(file, r) == l {
                        ranges[i].end = to_excerpt(r.end).max(ranges[i].start);
                    }
                }
            }
            ex.starts.push(ex.text.len());
            *slot = Some(ex);
        }
        (Excerpts { files }, ranges)
    }

    fn get(&self, id: usize) -> Result<&Excerpt<'a>, Error> {
        self.files
            .get(id)
            .and_then(Option::as_ref)
            .ok_or(Error::FileMissing)
    }
}

/// The byte range of `line` to show: all of it when short, else at most MAX_LINE_CHARS
/// characters from CONTEXT_CHARS before the first mark.
fn window(line: &str, marks: &[usize]) -> Range<usize> {
    if line.len() <= MAX_LINE_CHARS || line.chars().count() <= MAX_LINE_CHARS {
        return 0..line.len();
    }
    let first = marks.iter().copied().min().unwrap_or(0);
    let chars: Vec<usize> = line.char_indices().map(|(b, _)| b).collect();
    let at = chars.partition_point(|&b| b < first);
    let from = at.saturating_sub(CONTEXT_CHARS);
    let to = (from + MAX_LINE_CHARS).min(chars.len());
    chars[from]..chars.get(to).copied().unwrap_or(line.len())
}

impl<'a> Files<'a> for Excerpts<'a> {
    type FileId = usize;
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, id: usize) -> Result<&'a str, Error> {
        Ok(self.get(id)?.name)
    }
    fn source(&'a self, id: usize) -> Result<&'a str, Error> {
        Ok(self.get(id)?.text.as_str())
    }
    fn line_index(&'a self, id: usize, byte_index: usize) -> Result<usize, Error> {
        let ex = self.get(id)?;
        let lines = ex.numbers.len();
        Ok(ex
            .starts
            .partition_point(|&s| s <= byte_index)
            .saturating_sub(1)
            .min(lines.saturating_sub(1)))
    }
    fn line_number(&'a self, id: usize, line_index: usize) -> Result<usize, Error> {
        let ex = self.get(id)?;
        ex.numbers
            .get(line_index)
            .copied()
            .ok_or(Error::LineTooLarge {
                given: line_index,
                max: ex.numbers.len(),
            })
    }
    fn column_number(
        &'a self,
        id: usize,
        line_index: usize,
        byte_index: usize,
    ) -> Result<usize, Error> {
        let cols = self.get(id)?.columns.get(line_index).map_or(&[][..], |c| c);
        let k = cols.partition_point(|c| c.0 < byte_index);
        Ok(cols.get(k).or(cols.last()).map_or(1, |c| c.1))
    }
    fn line_range(&'a self, id: usize, line_index: usize) -> Result<Range<usize>, Error> {
        let ex = self.get(id)?;
        match (ex.starts.get(line_index), ex.starts.get(line_index + 1)) {
            (Some(&s), Some(&e)) => Ok(s..e),
            _ => Err(Error::LineTooLarge {
                given: line_index,
                max: ex.numbers.len(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn source(text: &str) -> Vec<SourceFile> {
        vec![SourceFile {
            name: "m.yaml".into(),
            text: text.into(),
        }]
    }

    #[test]
    fn plain_lines_need_no_excerpt() {
        let s = source("a: 1\nb: [1, 2]\n");
        let lines = SourceLines::new(&s);
        assert!(!lines.needs_excerpt(&[(0, 5..9)]));
        let s = source("a: \"L0\there\"\n");
        assert!(SourceLines::new(&s).needs_excerpt(&[(0, 3..12)]));
    }

    #[test]
    fn a_line_shown_between_labels_counts() {
        // Found by tests/fuzz_maps.rs: the renderer prints the one line between two
        // labelled lines, which held a U+2066.
        let s = source("a: 1\nb: \"\u{2066}x\"\nc: 3\n");
        let lines = SourceLines::new(&s);
        assert!(lines.needs_excerpt(&[(0, 0..1), (0, 17..18)]));
        assert!(!lines.needs_excerpt(&[(0, 0..1)]));
    }

    #[test]
    fn long_line_is_cut_around_the_label() {
        let mut text = String::from("x: [");
        for i in 0..20_000 {
            text.push_str(&format!("{i}, "));
        }
        text.push_str("]\n");
        let target = text.find("12345,").unwrap();
        let s = source(&text);
        let lines = SourceLines::new(&s);
        let labels = [(0, target..target + 5)];
        assert!(lines.needs_excerpt(&labels));
        let (ex, ranges) = Excerpts::new(&lines, &labels);
        let src = ex.source(0).unwrap();
        assert!(src.len() < 2 * MAX_LINE_CHARS, "{src}");
        assert!(
            src.starts_with('…') && src.trim_end().ends_with('…'),
            "{src}"
        );
        assert_eq!(&src[ranges[0].clone()], "12345");
        // The column is the real one.
        let line = ex.line_index(0, ranges[0].start).unwrap();
        assert_eq!(ex.line_number(0, line).unwrap(), 1);
        assert_eq!(
            ex.column_number(0, line, ranges[0].start).unwrap(),
            target + 1
        );
    }

    #[test]
    fn escapes_and_keeps_far_lines_apart() {
        let text = "a: 1\nname: \"L\u{202e}1\"\nc: 3\nd: 4\ne: 5\nf: 6\n";
        let s = source(text);
        let lines = SourceLines::new(&s);
        let at = text.find("name").unwrap();
        let f = text.find("f: 6").unwrap();
        let (ex, ranges) = Excerpts::new(&lines, &[(0, at..at + 4), (0, f..f + 4)]);
        let src = ex.source(0).unwrap();
        assert!(
            !src.chars().any(|c| c != '\n' && needs_escape(c)),
            "{src:?}"
        );
        assert!(src.contains("\\u{202e}"), "{src:?}");
        assert_eq!(&src[ranges[1].clone()], "f: 6");
        let l = ex.line_index(0, ranges[1].start).unwrap();
        assert_eq!(ex.line_number(0, l).unwrap(), 6);
        // Two blank lines between: the renderer shows a break.
        assert_eq!(l, 3);
    }
}
