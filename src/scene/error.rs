//! Why a scene could not be read, or one of its frames projected.

use crate::error::OptionError;
use crate::geom::quadric::QuadricError;
use crate::geom::transform::TransformError;
use crate::io::IoError;
use crate::stream::StreamError;
use crate::stripe::record::{NoMapping, StripeError};
use crate::text::ParseError;
use crate::texture::place::PlaceError;
use std::error::Error;
use std::fmt;

/// An error of [`super::Scene`]'s reading or projection. `Display` gives this
/// layer's words (`scene.json: record 3`); [`Error::source`] gives the cause,
/// so `{:#}` through `anyhow`, as the tools print it, reads
/// `scene.json: record 3: pattern.file is missing`.
#[derive(Debug)]
pub enum SceneError {
    /// The stream could not be opened or read.
    Io(IoError),
    /// The stream is malformed: JSON, a record's fields, objects.
    Stream(StreamError),
    /// One record cannot be drawn.
    Record {
        /// The stream as errors name it; `None` when the scene is being
        /// projected (the stream was named when it was read).
        input: Option<String>,
        /// The record's index in the stream.
        index: usize,
        /// Why (boxed: errors stay small on the success path).
        error: Box<RecordError>,
    },
    /// An instance past the 2^32nd record of its stream: draw order is 32
    /// bits (a record there is refused as it is read,
    /// [`RecordError::TooManyRecords`]).
    TooManyRecords,
    /// The scene expands to more polygons per frame than
    /// [`super::LoadOptions::max_polygons`] allows, first at record `index`.
    TooMuchWork {
        /// The record (or instance) where the count passed the limit.
        index: usize,
        /// The count there (saturated at `u64::MAX`).
        polygons: u64,
        /// The limit.
        limit: u64,
    },
}

/// Why one record of a scene cannot be drawn.
#[derive(Debug)]
pub enum RecordError {
    /// The record names both a pattern and a stripe texture.
    PatternAndStripe,
    /// The record's `"pattern"` has no `"file"`.
    NoPatternFile,
    /// The record's pattern file cannot be read.
    Pattern(ParseError),
    /// The record's image texture cannot be read, or is too large.
    Image(IoError),
    /// A texture state key of the record's `"pattern"` is wrong
    /// ([`crate::texture::state`]): the message names it.
    TextureState(String),
    /// The record's stripe texture cannot be read.
    Stripe(StripeError),
    /// The face gives its stripes no mapping.
    StripeMapping(NoMapping),
    /// The pattern cannot be placed on the face.
    Place(PlaceError),
    /// A quadric cannot be tessellated.
    Quadric(QuadricError),
    /// A record's own animated transform fails at a frame.
    Transform {
        /// The record's geometry key: `vertices`, `rect`, `circle`, `arc`,
        /// `sphere`, `cylinder`, `cone` or `disk`.
        kind: &'static str,
        /// The frame.
        frame: u64,
        /// Why.
        error: TransformError,
    },
    /// Smooth lighting on a texture composed by `blend_intrinsic` or
    /// `decal_intrinsic`, which mix the texel with the lit colour in a way
    /// only flat lighting gives exactly.
    SmoothCompose(crate::texture::compose::Compose),
    /// The record comes after the 4,294,967,296th of its stream: draw
    /// order is 32 bits.
    TooManyRecords,
    /// An instance's transform, with those of the instances placing it,
    /// overflows or is singular ([`Transform::then_checked`]).
    ///
    /// [`Transform::then_checked`]: crate::geom::transform::Transform::then_checked
    PlacedTransform {
        /// The object the instance places.
        object: String,
        /// Why.
        error: TransformError,
    },
    /// An instance's animated transform fails at a frame.
    InstanceTransform {
        /// The object the instance places.
        object: String,
        /// The frame.
        frame: u64,
        /// Why.
        error: TransformError,
    },
}

impl RecordError {
    /// The error that carries the message: the wrapped library error itself
    /// for the variants that add no words of their own, so that a front end
    /// walking the chain meets, say, the [`PlaceError`] it rewords.
    fn as_cause(&self) -> &(dyn Error + 'static) {
        match self {
            RecordError::Pattern(e) => e,
            RecordError::Image(e) => e,
            RecordError::Stripe(e) => e,
            RecordError::StripeMapping(e) => e,
            RecordError::Place(e) => e,
            RecordError::Quadric(e) => e,
            _ => self,
        }
    }
}

impl fmt::Display for RecordError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RecordError::PatternAndStripe => {
                f.write_str("has both \"pattern\" and \"stripe\": a face takes one texture")
            }
            RecordError::NoPatternFile => f.write_str("pattern.file is missing"),
            RecordError::TooManyRecords => {
                f.write_str("more than 2^32 records in one stream: draw order is 32 bits")
            }
            RecordError::TextureState(m) => f.write_str(m),
            RecordError::Pattern(e) => e.fmt(f),
            RecordError::Image(e) => e.fmt(f),
            RecordError::Stripe(e) => e.fmt(f),
            RecordError::StripeMapping(e) => e.fmt(f),
            RecordError::Place(e) => e.fmt(f),
            RecordError::Quadric(e) => e.fmt(f),
            RecordError::Transform { kind, frame, .. } => {
                write!(f, "{kind}: transform at frame {frame}")
            }
            RecordError::InstanceTransform { object, frame, .. } => {
                write!(f, "instance of `{object}` at frame {frame}")
            }
            RecordError::PlacedTransform { object, .. } => write!(
                f,
                "instance of `{object}`: its transform with those of the instances placing it"
            ),
            RecordError::SmoothCompose(c) => write!(
                f,
                "smooth lighting with compose {}: it mixes the texel with the lit colour, which is exact only when flat: give the record \"shade\": \"flat\", or compose modulate",
                c.name()
            ),
        }
    }
}

impl Error for RecordError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        match self {
            RecordError::Transform { error, .. }
            | RecordError::InstanceTransform { error, .. }
            | RecordError::PlacedTransform { error, .. } => Some(error),
            RecordError::PatternAndStripe
            | RecordError::NoPatternFile
            | RecordError::TooManyRecords
            | RecordError::TextureState(_)
            | RecordError::SmoothCompose(_) => None,
            other => other.as_cause().source(),
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Io(e) => e.fmt(f),
            SceneError::Stream(e) => e.fmt(f),
            SceneError::Record {
                input: Some(input),
                index,
                ..
            } => write!(f, "{input}: record {index}"),
            SceneError::Record {
                input: None, index, ..
            } => write!(f, "record {index}"),
            SceneError::TooManyRecords => f.write_str("more than 2^32 records"),
            SceneError::TooMuchWork {
                index,
                polygons,
                limit,
            } => {
                let polygons = match *polygons {
                    u64::MAX => "more than 2^64 polygons".to_string(),
                    1 => "1 polygon".to_string(),
                    n => format!("{n} polygons"),
                };
                write!(
                    f,
                    "record {index}: the scene expands to {polygons} in a frame \
                     by here (instances times their objects' polygons, an empty one's counting \
                     one, quadrics their \
                     triangles, at most slices x stacks x 2, given or as fine as the view \
                     needs), \
                     over the limit of {limit}"
                )
            }
        }
    }
}

impl Error for SceneError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        match self {
            SceneError::Io(e) => e.source(),
            SceneError::Stream(e) => e.source(),
            SceneError::Record { error, .. } => Some(error.as_cause()),
            SceneError::TooManyRecords | SceneError::TooMuchWork { .. } => None,
        }
    }
}

impl From<StreamError> for SceneError {
    fn from(e: StreamError) -> SceneError {
        SceneError::Stream(e)
    }
}

impl From<IoError> for SceneError {
    fn from(e: IoError) -> SceneError {
        SceneError::Io(e)
    }
}

/// Attaches a record's index (and, while reading, the stream's name) to the
/// error of one record.
pub(super) trait InRecord<T> {
    fn in_record(self, input: Option<&str>, index: usize) -> Result<T, SceneError>;
}

impl<T, E: Into<RecordError>> InRecord<T> for Result<T, E> {
    fn in_record(self, input: Option<&str>, index: usize) -> Result<T, SceneError> {
        self.map_err(|e| SceneError::Record {
            input: input.map(str::to_string),
            index,
            error: Box::new(e.into()),
        })
    }
}

/// `From` for each error an enum wraps whole, as `Enum::Variant(error)`.
macro_rules! wraps {
    ($enum:ident: $($variant:ident($ty:ty)),*) => {
        $(impl From<$ty> for $enum {
            fn from(e: $ty) -> $enum {
                $enum::$variant(e)
            }
        })*
    };
}

impl From<crate::texture::texels::LoadError> for RecordError {
    fn from(e: crate::texture::texels::LoadError) -> RecordError {
        use crate::texture::texels::LoadError;
        match e {
            LoadError::Pattern(e) => RecordError::Pattern(e),
            LoadError::Image(e) => RecordError::Image(e),
        }
    }
}

wraps!(
    RecordError:
    Pattern(ParseError),
    Stripe(StripeError),
    StripeMapping(NoMapping),
    Place(PlaceError),
    Quadric(QuadricError)
);

/// An error of [`super::polyfill::partition_stream`]. As with
/// [`SceneError`], `Display` gives this layer's words and
/// [`Error::source`] the cause.
#[derive(Debug)]
pub enum PartitionError {
    /// The stream is malformed: JSON, a record's fields, objects.
    Stream(StreamError),
    /// One record cannot be partitioned.
    Record {
        /// The stream as errors name it.
        input: String,
        /// The record's index in the stream (for a record inside an object
        /// definition, the definition's).
        index: usize,
        /// For a record inside an object definition: the object's name and
        /// the record's place in its `"records"`.
        within: Option<(String, usize)>,
        /// Why (boxed: errors stay small on the success path).
        error: Box<CellsError>,
    },
    /// The output could not be written.
    Write(std::io::Error),
}

/// Why one record cannot be partitioned into texel cells.
#[derive(Debug)]
pub enum CellsError {
    /// An option does not allow it: no pattern file anywhere, the polygon
    /// limit, integer shifts for the thesis's algorithm.
    Option(OptionError),
    /// The pattern file cannot be read.
    Pattern(ParseError),
    /// A file's path cannot be made for the output (the current directory
    /// is gone).
    PatternPath {
        /// The path as resolved.
        path: std::path::PathBuf,
        /// The cause.
        error: std::io::Error,
    },
    /// A quadric cannot be tessellated.
    Quadric(QuadricError),
    /// The polygon has no plane.
    Plane(crate::geom::plane::PlaneError),
    /// The texel grid over the polygon cannot be made.
    Grid(crate::geom::partition::GridError),
    /// The texture coordinates of a `uv` record cannot be made.
    Uv(crate::texture::map::ObjectUvError),
    /// A texture state key of the record's `"pattern"` is wrong
    /// ([`crate::texture::state`]): the message names it.
    TextureState(String),
    /// The output could not be written.
    Write(std::io::Error),
}

impl CellsError {
    /// As [`RecordError::as_cause`]: the wrapped error for variants that add
    /// no words, so that a front end meets the [`OptionError`] it rewords.
    fn as_cause(&self) -> &(dyn Error + 'static) {
        match self {
            CellsError::Option(e) => e,
            CellsError::Quadric(e) => e,
            CellsError::Plane(e) => e,
            CellsError::Grid(e) => e,
            CellsError::Uv(e) => e,
            CellsError::Write(e) => e,
            CellsError::Pattern(_)
            | CellsError::PatternPath { .. }
            | CellsError::TextureState(_) => self,
        }
    }
}

impl fmt::Display for CellsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CellsError::Pattern(_) => f.write_str("pattern"),
            CellsError::PatternPath { path, .. } => write!(f, "pattern: {}", path.display()),
            CellsError::TextureState(m) => f.write_str(m),
            other => fmt::Display::fmt(other.as_cause(), f),
        }
    }
}

impl Error for CellsError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        match self {
            CellsError::Pattern(e) => Some(e),
            CellsError::PatternPath { error, .. } => Some(error),
            CellsError::TextureState(_) => None,
            other => other.as_cause().source(),
        }
    }
}

impl fmt::Display for PartitionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PartitionError::Stream(e) => e.fmt(f),
            PartitionError::Record {
                input,
                index,
                within,
                ..
            } => {
                write!(f, "{input}: record {index}")?;
                match within {
                    Some((name, i)) => write!(f, ": object `{name}` records[{i}]"),
                    None => Ok(()),
                }
            }
            PartitionError::Write(e) => e.fmt(f),
        }
    }
}

impl Error for PartitionError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        match self {
            PartitionError::Stream(_) => None,
            PartitionError::Record { error, .. } => Some(error.as_cause()),
            PartitionError::Write(e) => e.source(),
        }
    }
}

impl From<StreamError> for PartitionError {
    fn from(e: StreamError) -> PartitionError {
        PartitionError::Stream(e)
    }
}

impl From<std::io::Error> for PartitionError {
    fn from(e: std::io::Error) -> PartitionError {
        PartitionError::Write(e)
    }
}

wraps!(
    CellsError:
    Option(OptionError),
    Quadric(QuadricError),
    Plane(crate::geom::plane::PlaneError),
    Grid(crate::geom::partition::GridError),
    Uv(crate::texture::map::ObjectUvError),
    Write(std::io::Error)
);
