//! Spans, the source map, file loading, and rendering of diagnostics.
//!
//! Phase errors carry [`Span`]s (file id + byte range), never source text. The
//! text is attached only when a report is printed ([`render_one`], [`render_all`]), so errors stay
//! small, `Copy`-friendly and comparable in tests.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use miette::{Diagnostic, GraphicalReportHandler, GraphicalTheme, NamedSource, SourceSpan};

/// Index of a file in a [`SourceMap`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct FileId(pub u32);

/// A byte range in one source file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Span {
    pub file: FileId,
    pub start: u32,
    pub end: u32,
}

impl Span {
    pub fn new(file: FileId, start: usize, end: usize) -> Span {
        // Files are capped well below 4 GiB by the loader, so this never saturates in practice.
        let clamp = |x: usize| u32::try_from(x).unwrap_or(u32::MAX);
        Span { file, start: clamp(start), end: clamp(end.max(start)) }
    }

    /// The smallest span covering both (same file assumed; `self`'s file wins).
    pub fn to(self, other: Span) -> Span {
        Span { file: self.file, start: self.start.min(other.start), end: self.end.max(other.end) }
    }

    pub fn len(&self) -> usize {
        (self.end - self.start) as usize
    }

    pub fn is_empty(&self) -> bool {
        self.end == self.start
    }
}

impl From<Span> for SourceSpan {
    fn from(s: Span) -> SourceSpan {
        SourceSpan::new((s.start as usize).into(), s.len())
    }
}

/// One loaded source file.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// The path as the user should read it in a report (relative where possible).
    pub name: String,
    /// The path used to open the file and to resolve paths relative to it.
    pub path: PathBuf,
    pub text: String,
}

/// Every source file read while compiling one scenario.
#[derive(Debug, Clone, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    pub fn new() -> SourceMap {
        SourceMap::default()
    }

    pub fn add(&mut self, name: impl Into<String>, path: impl Into<PathBuf>, text: impl Into<String>) -> FileId {
        let id = FileId(self.files.len() as u32);
        self.files.push(SourceFile { name: name.into(), path: path.into(), text: text.into() });
        id
    }

    pub fn get(&self, id: FileId) -> Option<&SourceFile> {
        self.files.get(id.0 as usize)
    }

    pub fn files(&self) -> impl Iterator<Item = (FileId, &SourceFile)> {
        self.files.iter().enumerate().map(|(i, f)| (FileId(i as u32), f))
    }

    /// The file already loaded from `path`, if any.
    pub fn find(&self, path: &Path) -> Option<FileId> {
        self.files.iter().position(|f| f.path == path).map(|i| FileId(i as u32))
    }

    /// The byte offset of a 1-based line and (character) column in a file, as YAML and
    /// JSON parsers report positions.
    pub fn offset_of(&self, file: FileId, line: u64, column: u64) -> Option<usize> {
        let text = &self.get(file)?.text;
        let start: usize = text.split_inclusive('\n').take(line.checked_sub(1)? as usize).map(str::len).sum();
        let line_text = text.get(start..)?.split('\n').next()?;
        let col: usize = line_text.chars().take(column.saturating_sub(1) as usize).map(char::len_utf8).sum();
        Some(start + col)
    }

    /// 1-based line and column of a span's start, for one-line messages.
    pub fn line_col(&self, span: Span) -> Option<(usize, usize)> {
        let f = self.get(span.file)?;
        let upto = f.text.get(..span.start as usize)?;
        let line = upto.matches('\n').count() + 1;
        let col = upto.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        Some((line, col))
    }
}

/// All file access goes through this trait, so tests can use an in-memory file set.
pub trait Loader: Sync {
    fn read_to_string(&self, path: &Path) -> io::Result<String>;
    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>>;
    fn exists(&self, path: &Path) -> bool;
    /// What is at a `path` that [`Loader::exists`] refused, so that "no such file" is
    /// said only when it is true.
    fn what_is(&self, _path: &Path) -> NotAFile {
        NotAFile::Missing
    }
}

/// What stands where a file was expected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NotAFile {
    Missing,
    Directory,
    /// A device, FIFO or socket: reading it may never end (`/dev/zero`, a pipe).
    Special,
}

impl NotAFile {
    /// "does not exist", "is a directory", ...
    pub fn predicate(self) -> &'static str {
        match self {
            NotAFile::Missing => "does not exist",
            NotAFile::Directory => "is a directory",
            NotAFile::Special => "is not a regular file",
        }
    }
    /// The help line, `dir` being the directory the path is relative to.
    pub fn help(self, dir: &str) -> String {
        match self {
            NotAFile::Special => {
                "name a regular file: declutter reads files whole, and a device or pipe may never end".to_string()
            }
            _ => format!("paths are relative to the directory of the file that names them ({dir})"),
        }
    }
    /// The label under the path.
    pub fn label(self) -> &'static str {
        match self {
            NotAFile::Missing => "no such file",
            NotAFile::Directory => "a directory, not a file",
            NotAFile::Special => "a device, pipe or socket, not a file",
        }
    }
}

/// Largest scenario, URDF or mesh file we accept; beyond it a file is surely a mistake.
pub const MAX_FILE_BYTES: u64 = 256 * 1024 * 1024;

/// The real file system.
#[derive(Debug, Default, Clone, Copy)]
pub struct FsLoader;

impl Loader for FsLoader {
    fn read_to_string(&self, path: &Path) -> io::Result<String> {
        check_size(path)?;
        std::fs::read_to_string(path)
    }
    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        check_size(path)?;
        std::fs::read(path)
    }
    fn exists(&self, path: &Path) -> bool {
        path.is_file()
    }
    fn what_is(&self, path: &Path) -> NotAFile {
        match std::fs::metadata(path) {
            Ok(m) if m.is_dir() => NotAFile::Directory,
            Ok(m) if !m.is_file() => NotAFile::Special,
            _ => NotAFile::Missing,
        }
    }
}

fn check_size(path: &Path) -> io::Result<()> {
    let meta = std::fs::metadata(path)?;
    if meta.is_dir() {
        return Err(io::Error::other("is a directory, not a file"));
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(io::Error::other(format!(
            "file is {} bytes, more than the {} byte limit",
            meta.len(),
            MAX_FILE_BYTES
        )));
    }
    Ok(())
}

/// An in-memory file set for tests and fuzzing.
#[derive(Debug, Default, Clone)]
pub struct MemLoader {
    files: std::collections::BTreeMap<PathBuf, Vec<u8>>,
}

impl MemLoader {
    pub fn new() -> MemLoader {
        MemLoader::default()
    }
    pub fn with(mut self, path: impl Into<PathBuf>, contents: impl Into<Vec<u8>>) -> MemLoader {
        self.files.insert(path.into(), contents.into());
        self
    }
    pub fn insert(&mut self, path: impl Into<PathBuf>, contents: impl Into<Vec<u8>>) {
        self.files.insert(path.into(), contents.into());
    }
}

impl Loader for MemLoader {
    fn read_to_string(&self, path: &Path) -> io::Result<String> {
        let bytes = self.read_bytes(path)?;
        String::from_utf8(bytes).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))
    }
    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        self.files.get(path).cloned().ok_or_else(|| io::Error::from(io::ErrorKind::NotFound))
    }
    fn exists(&self, path: &Path) -> bool {
        self.files.contains_key(path)
    }
}

/// A phase error that knows which file its labels point into.
pub trait Located {
    /// The span of the primary label, if the error has one.
    fn primary_span(&self) -> Option<Span>;

    /// Places in other files than the primary span's (e.g. the first declaration of a
    /// name declared again in a used file), with their labels. A miette label can only
    /// point into one source, so each is drawn as a related report with its own file.
    fn elsewhere(&self) -> Vec<(Span, String)> {
        Vec::new()
    }
}

/// A label in another file, drawn under the main report.
#[derive(Debug)]
struct Elsewhere {
    /// The main report's code, so the related report's header line is not empty.
    code: Option<String>,
    label: String,
    span: Span,
    src: NamedSource<String>,
}

impl fmt::Display for Elsewhere {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "in {}", self.src.name())
    }
}
impl std::error::Error for Elsewhere {}

impl Diagnostic for Elsewhere {
    fn code<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        self.code.as_ref().map(|c| Box::new(c) as Box<dyn fmt::Display>)
    }
    fn severity(&self) -> Option<miette::Severity> {
        Some(miette::Severity::Advice)
    }
    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(&self.src)
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        let l = miette::LabeledSpan::new_with_span(Some(self.label.clone()), SourceSpan::from(self.span));
        Some(Box::new(std::iter::once(l)))
    }
}

/// Attaches the right source file to a phase error for printing.
struct WithSource<'a> {
    inner: &'a dyn Diagnostic,
    src: Option<NamedSource<String>>,
    elsewhere: Vec<Elsewhere>,
}

impl fmt::Debug for WithSource<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.inner, f)
    }
}
impl fmt::Display for WithSource<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self.inner, f)
    }
}
impl std::error::Error for WithSource<'_> {}

impl Diagnostic for WithSource<'_> {
    fn code<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        self.inner.code()
    }
    fn severity(&self) -> Option<miette::Severity> {
        self.inner.severity()
    }
    fn help<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        self.inner.help()
    }
    fn url<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        self.inner.url()
    }
    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        self.src.as_ref().map(|s| s as &dyn miette::SourceCode).or_else(|| self.inner.source_code())
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        self.inner.labels()
    }
    fn related<'b>(&'b self) -> Option<Box<dyn Iterator<Item = &'b dyn Diagnostic> + 'b>> {
        let own = self.elsewhere.iter().map(|e| e as &dyn Diagnostic);
        match self.inner.related() {
            Some(r) => Some(Box::new(r.chain(own))),
            None if self.elsewhere.is_empty() => None,
            None => Some(Box::new(own)),
        }
    }
    fn diagnostic_source(&self) -> Option<&dyn Diagnostic> {
        self.inner.diagnostic_source()
    }
}

/// How reports are drawn.
#[derive(Debug, Clone, Copy)]
pub struct RenderOptions {
    pub color: bool,
    pub width: usize,
}

impl RenderOptions {
    /// Plain text at a fixed width: what snapshot tests pin.
    pub fn plain() -> RenderOptions {
        RenderOptions { color: false, width: 100 }
    }
}

/// Longest source line a graphical report is drawn for: miette cannot pad beyond
/// 65535 columns, so a label on a longer line is reported as `file:line:col: message`.
const MAX_DRAWN_LINE: usize = 10_000;

fn drawable(sources: &SourceMap, err: &dyn Diagnostic, primary: Option<Span>) -> bool {
    let Some(file) = primary.and_then(|s| sources.get(s.file)) else { return true };
    err.labels().into_iter().flatten().all(|l| line_len(&file.text, l.offset()) <= MAX_DRAWN_LINE)
}

/// Length in bytes of the line holding byte `at`.
fn line_len(text: &str, at: usize) -> usize {
    let at = at.min(text.len());
    let start = text.get(..at).and_then(|t| t.rfind('\n')).map_or(0, |i| i + 1);
    let end = text.get(at..).and_then(|t| t.find('\n')).map_or(text.len(), |i| at + i);
    end - start
}

/// Renders one diagnostic with the source of the file its primary span points into.
pub fn render_one<E: Diagnostic + Located>(sources: &SourceMap, err: &E, opts: RenderOptions) -> String {
    let primary = err.primary_span();
    if !drawable(sources, err, primary) {
        let place = primary
            .and_then(|s| Some((sources.get(s.file)?.name.clone(), sources.line_col(s)?)))
            .map_or_else(String::new, |(n, (l, c))| format!("{n}:{l}:{c}: "));
        let code = err.code().map(|c| format!(" [{c}]")).unwrap_or_default();
        let mut out = format!("error{code}: {place}{err}\n");
        if let Some(h) = err.help() {
            out.push_str(&format!("  help: {h}\n"));
        }
        for (span, label) in err.elsewhere() {
            if let (Some(f), Some((l, c))) = (sources.get(span.file), sources.line_col(span)) {
                out.push_str(&format!("  note: {}:{l}:{c}: {label}\n", f.name));
            }
        }
        return out;
    }
    let src = primary.and_then(|s| sources.get(s.file)).map(|f| NamedSource::new(f.name.clone(), f.text.clone()));
    let code = err.code().map(|c| c.to_string());
    let elsewhere = err
        .elsewhere()
        .into_iter()
        .filter_map(|(span, label)| {
            let f = sources.get(span.file)?;
            // The same long-line limit as the main report: such a place is named, not drawn.
            (line_len(&f.text, span.start as usize) <= MAX_DRAWN_LINE).then(|| Elsewhere {
                code: code.clone(),
                label,
                span,
                src: NamedSource::new(f.name.clone(), f.text.clone()),
            })
        })
        .collect();
    let wrapped = WithSource { inner: err, src, elsewhere };
    let theme = if opts.color { GraphicalTheme::unicode() } else { GraphicalTheme::unicode_nocolor() };
    let handler = GraphicalReportHandler::new_themed(theme).with_width(opts.width).with_links(false);
    let mut out = String::new();
    if handler.render_report(&mut out, &wrapped).is_err() {
        out = format!("error: {err}\n");
    }
    out
}

/// Renders several diagnostics, sorted by position for stable output.
pub fn render_all<E: Diagnostic + Located>(sources: &SourceMap, errs: &[E], opts: RenderOptions) -> String {
    let mut order: Vec<&E> = errs.iter().collect();
    order.sort_by_key(|e| e.primary_span());
    order.iter().map(|e| render_one(sources, *e, opts)).collect::<Vec<_>>().join("\n")
}
