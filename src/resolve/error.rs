//! Everything `resolve` can reject, each with a stable code and the span to blame.

use miette::Diagnostic;
use thiserror::Error;

use crate::diag::{Located, Span};
use crate::syntax::SyntaxError;

#[derive(Debug, Clone, PartialEq, Error, Diagnostic)]
pub enum ResolveError {
    /// A syntax error in the root file or in a `use`d file (boxed: it is the largest).
    #[error(transparent)]
    #[diagnostic(transparent)]
    Syntax(Box<SyntaxError>),

    #[error("cannot read `{path}`: {reason}")]
    #[diagnostic(code(declutter::resolve::unreadable))]
    Unreadable {
        path: String,
        reason: String,
        /// The `use` that names the file; `None` for the file given on the command line.
        #[label("named here")]
        span: Option<Span>,
    },

    #[error("`use` cycle: {chain}")]
    #[diagnostic(
        code(declutter::resolve::use_cycle),
        help("a file may not use itself, directly or through other files")
    )]
    UseCycle {
        chain: String,
        #[label("this `use` closes the cycle")]
        span: Span,
    },

    #[error("{what} file `{path}` {}", found.predicate())]
    #[diagnostic(code(declutter::resolve::missing_file))]
    MissingFile {
        what: &'static str,
        path: String,
        /// Built by [`crate::diag::NotAFile::help`].
        #[help]
        help: String,
        /// What is there instead of a file.
        found: crate::diag::NotAFile,
        #[label("{}", found.label())]
        span: Span,
    },

    #[error("`{path}` is not UTF-8 text: invalid byte at line {line}, column {column}")]
    #[diagnostic(
        code(declutter::resolve::not_utf8),
        help("scenario files are UTF-8; re-save the file as UTF-8 or remove the stray byte")
    )]
    NotUtf8 {
        path: String,
        line: usize,
        column: usize,
        #[label("not UTF-8")]
        span: Span,
        /// The `use` that names the file (drawn as a related report: it is in another file).
        used_at: Option<Span>,
    },

    #[error("unknown {kind} `{name}`")]
    #[diagnostic(code(declutter::resolve::unknown_name))]
    UnknownName {
        kind: &'static str,
        name: String,
        #[label("no {kind} has this name")]
        span: Span,
        #[help]
        help: Option<String>,
    },

    #[error("`{name}` is {found}, not {expected}")]
    #[diagnostic(code(declutter::resolve::wrong_kind))]
    WrongKind {
        name: String,
        expected: &'static str,
        found: &'static str,
        #[label("expected {expected}")]
        span: Span,
        #[label("`{name}` is declared here")]
        decl: Option<Span>,
        /// Where `name` is declared, when that is in another file (drawn as a related report).
        elsewhere: Option<Span>,
    },

    #[error("`{name}` is declared twice")]
    #[diagnostic(code(declutter::resolve::duplicate_name))]
    DuplicateName {
        name: String,
        #[label("declared again here")]
        span: Span,
        /// The first declaration, when it is in the same file.
        #[label("first declared here")]
        first: Option<Span>,
        /// The first declaration, when it is in another file (drawn as a related report).
        elsewhere: Option<Span>,
        #[help]
        help: Option<String>,
    },

    #[error("expected {expected}, found {found}")]
    #[diagnostic(code(declutter::resolve::unit_mismatch))]
    UnitMismatch {
        expected: &'static str,
        found: String,
        #[label("expected {expected}")]
        span: Span,
        #[help]
        help: Option<String>,
    },

    #[error("unknown unit `{unit}`")]
    #[diagnostic(code(declutter::resolve::unknown_unit))]
    UnknownUnit {
        unit: String,
        #[label("not a unit")]
        span: Span,
        #[help]
        help: String,
    },

    #[error("{what} takes {expected}, found {found}")]
    #[diagnostic(code(declutter::resolve::wrong_count))]
    WrongCount {
        what: String,
        expected: String,
        found: usize,
        #[label("{found} given here")]
        span: Span,
    },

    #[error("this number is not finite")]
    #[diagnostic(
        code(declutter::resolve::not_finite),
        help("numbers must be finite; this one overflows a 64-bit float")
    )]
    NotFinite {
        #[label("too large to represent")]
        span: Span,
    },

    #[error("{what} must be {limit}, found {value}")]
    #[diagnostic(code(declutter::resolve::out_of_range))]
    OutOfRange {
        what: String,
        limit: String,
        value: String,
        #[label("out of range")]
        span: Span,
        #[help]
        help: Option<String>,
    },

    #[error("a bare angle of {value} is {value} radians, more than a full turn")]
    #[diagnostic(code(declutter::resolve::bare_angle))]
    BareAngle {
        value: String,
        #[label("radians, since no unit is given")]
        span: Span,
        #[help]
        help: String,
    },

    #[error("`quat(x, y, z, w)` must be a unit quaternion, found norm {norm}")]
    #[diagnostic(code(declutter::resolve::bad_quaternion))]
    BadQuaternion {
        norm: String,
        #[label("norm {norm}")]
        span: Span,
        #[help]
        help: String,
    },

    #[error("{what} must be a whole number, found `{value}`")]
    #[diagnostic(code(declutter::resolve::not_integer))]
    NotInteger {
        what: String,
        value: String,
        #[label("not a whole number")]
        span: Span,
    },

    #[error("`repeat 0` makes no grasps")]
    #[diagnostic(
        code(declutter::resolve::repeat_zero),
        help("use `repeat 1` (or leave `repeat` out) for a single grasp")
    )]
    RepeatZero {
        #[label("must be at least 1")]
        span: Span,
    },

    #[error("grasp `{grasp}` on fixed body `{body}`")]
    #[diagnostic(
        code(declutter::resolve::grasp_on_fixed),
        help("fixed bodies are never moved; declare `{body}` with `object` if a robot may remove it")
    )]
    GraspOnFixed {
        grasp: String,
        body: String,
        #[label("grasps are only allowed on objects")]
        span: Span,
        #[label("declared `fixed` here")]
        kind: Span,
    },

    #[error("the scenario has no `target`")]
    #[diagnostic(
        code(declutter::resolve::missing_target),
        help("add `target OBJECT` (grasp that object) or `target ROBOT at [joint values]`")
    )]
    MissingTarget {
        #[label("in this scenario")]
        span: Span,
    },

    #[error("more than one `target`")]
    #[diagnostic(code(declutter::resolve::duplicate_target), help("a scenario has exactly one target"))]
    DuplicateTarget {
        #[label("second target")]
        span: Span,
        #[label("first target")]
        first: Option<Span>,
    },

    #[error("`{what}` in a used file")]
    #[diagnostic(code(declutter::resolve::not_in_used_file), help("`scenario` and `target` belong to the file given on the command line; a used file only contributes declarations"))]
    NotInUsedFile {
        what: &'static str,
        #[label("only allowed in the root file")]
        span: Span,
    },

    #[error("the scenario has no robot")]
    #[diagnostic(
        code(declutter::resolve::no_robot),
        help("declare at least one `robot NAME {{ ... }}`, or `use` a cell file that does")
    )]
    NoRobot {
        #[label("in this scenario")]
        span: Span,
    },

    #[error("{decl} `{name}` has no `{what}`")]
    #[diagnostic(code(declutter::resolve::missing_statement))]
    MissingStatement {
        decl: &'static str,
        name: String,
        what: &'static str,
        #[label("needs a `{what}` statement")]
        span: Span,
        #[help]
        help: Option<String>,
    },

    #[error("hand `{name}` is listed twice in `for`")]
    #[diagnostic(code(declutter::resolve::duplicate_in_list), help("list each hand once"))]
    DuplicateInList {
        name: String,
        #[label("listed again here")]
        span: Span,
        #[label("first listed here")]
        first: Span,
    },

    #[error("`{what}` given twice")]
    #[diagnostic(code(declutter::resolve::duplicate_statement))]
    DuplicateStatement {
        what: String,
        #[label("given again here")]
        span: Span,
        #[label("first given here")]
        first: Span,
    },

    #[error("{kind} `{name}` has no shape")]
    #[diagnostic(
        code(declutter::resolve::no_shape),
        help(
            "give a shape after the name (`{kind} {name} box(10cm, 10cm, 10cm) at (...)`) or list shapes in its block"
        )
    )]
    NoShape {
        kind: &'static str,
        name: String,
        #[label("no shape")]
        span: Span,
    },

    #[error("{problem}")]
    #[diagnostic(code(declutter::resolve::shape_argument))]
    ShapeArgument {
        problem: String,
        #[label("here")]
        span: Span,
        #[help]
        help: Option<String>,
    },

    #[error("unknown planner setting `{key}`")]
    #[diagnostic(code(declutter::resolve::unknown_planner_key))]
    UnknownPlannerKey {
        key: String,
        #[label("not a planner setting")]
        span: Span,
        #[help]
        help: String,
    },

    #[error("invalid value for `{key}`: expected {expected}")]
    #[diagnostic(code(declutter::resolve::bad_planner_value))]
    BadPlannerValue {
        key: String,
        expected: String,
        #[label("expected {expected}")]
        span: Span,
        #[help]
        help: Option<String>,
    },

    #[error("{problem}")]
    #[diagnostic(code(declutter::resolve::bad_target))]
    BadTarget {
        problem: String,
        #[label("here")]
        span: Span,
        #[help]
        help: Option<String>,
    },

    #[error("`{robot}` has {expected} joint values in `home`, but {found} here")]
    #[diagnostic(
        code(declutter::resolve::joint_count),
        help("every joint vector of a robot lists one value per joint, like its `home`")
    )]
    JointCount {
        robot: String,
        expected: usize,
        found: usize,
        #[label("{found} values")]
        span: Span,
        #[label("{expected} values")]
        home: Option<Span>,
    },
}

impl Located for ResolveError {
    fn primary_span(&self) -> Option<Span> {
        use ResolveError::*;
        match self {
            Syntax(e) => e.primary_span(),
            Unreadable { span, .. } => *span,
            UseCycle { span, .. }
            | MissingFile { span, .. }
            | NotUtf8 { span, .. }
            | UnknownName { span, .. }
            | WrongKind { span, .. }
            | DuplicateName { span, .. }
            | UnitMismatch { span, .. }
            | UnknownUnit { span, .. }
            | WrongCount { span, .. }
            | NotFinite { span }
            | OutOfRange { span, .. }
            | BareAngle { span, .. }
            | BadQuaternion { span, .. }
            | NotInteger { span, .. }
            | RepeatZero { span }
            | GraspOnFixed { span, .. }
            | MissingTarget { span }
            | DuplicateTarget { span, .. }
            | NotInUsedFile { span, .. }
            | NoRobot { span }
            | MissingStatement { span, .. }
            | DuplicateStatement { span, .. }
            | DuplicateInList { span, .. }
            | NoShape { span, .. }
            | ShapeArgument { span, .. }
            | UnknownPlannerKey { span, .. }
            | BadPlannerValue { span, .. }
            | BadTarget { span, .. }
            | JointCount { span, .. } => Some(*span),
        }
    }

    fn elsewhere(&self) -> Vec<(Span, String)> {
        match self {
            ResolveError::DuplicateName { name, elsewhere: Some(s), .. } => {
                vec![(*s, format!("`{name}` first declared here"))]
            }
            ResolveError::WrongKind { name, elsewhere: Some(s), .. } => {
                vec![(*s, format!("`{name}` is declared here"))]
            }
            ResolveError::NotUtf8 { used_at: Some(s), .. } => vec![(*s, "used here".to_string())],
            _ => Vec::new(),
        }
    }
}

/// Something valid but probably not what was meant; `check` prints it and still succeeds.
#[derive(Debug, Clone, PartialEq, Error, Diagnostic)]
pub enum ResolveWarning {
    #[error("the file declares objects but no `target`")]
    #[diagnostic(
        code(declutter::resolve::no_target),
        severity(Warning),
        help("it is checked as a library (like a cell file); add `target OBJECT` to make it a scenario")
    )]
    ObjectsWithoutTarget {
        #[label("an object, but nothing to do with it")]
        span: Span,
    },

    #[error("a bare length of {value} is {value} metres, larger than a robot cell")]
    #[diagnostic(code(declutter::resolve::large_bare_length))]
    LargeBareLength {
        value: String,
        #[label("metres, since no unit is given")]
        span: Span,
        #[help]
        help: String,
    },
}

impl Located for ResolveWarning {
    fn primary_span(&self) -> Option<Span> {
        match self {
            ResolveWarning::ObjectsWithoutTarget { span } | ResolveWarning::LargeBareLength { span, .. } => Some(*span),
        }
    }
}

impl ResolveWarning {
    /// The stable code, e.g. `declutter::resolve::no_target`.
    pub fn code_str(&self) -> String {
        self.code().map(|c| c.to_string()).unwrap_or_default()
    }
}

impl ResolveError {
    /// The stable code, e.g. `declutter::resolve::unit_mismatch`.
    pub fn code_str(&self) -> String {
        self.code().map(|c| c.to_string()).unwrap_or_default()
    }
}
