//! Why an input could not be used: each a sentence for the robot's operator, logged once per
//! kind by [`crate::once::LogOnce`] and answered with nothing.

/// What was wrong with what arrived on a topic.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InputError {
    #[error(
        "the camera image is `{0}`; only rgb8 and bgr8 are read (set the camera driver to one)"
    )]
    ImageEncoding(String),
    #[error("the camera image is malformed: {0}")]
    ImageShape(String),
    #[error("the point cloud has no float32 `{0}` field; x, y and z must be float32")]
    CloudField(&'static str),
    #[error(
        "the depth image is `{0}`; only 16UC1 (millimetres) and 32FC1 (metres) are read (publish \
         the driver's aligned depth)"
    )]
    DepthEncoding(String),
    #[error("the depth image is malformed: {0}")]
    DepthShape(String),
    #[error("the point cloud is malformed: {0}")]
    CloudShape(String),
    #[error("the point cloud is big-endian; only little-endian clouds are read")]
    CloudBigEndian,
    #[error("the camera info is unusable: {0}")]
    CameraInfo(String),
    #[error("a point was clicked before any {0} arrived")]
    Missing(&'static str),
    #[error("no transform from `{from}` to `{to}` has arrived on /tf_static")]
    NoTransform { from: String, to: String },
    #[error("the click is in frame `{got}`, but the cloud and the waypoint are in `{base}`")]
    ClickFrame { got: String, base: String },
    #[error("the point cloud is in frame `{got}`, not the base frame `{base}`")]
    CloudFrame { got: String, base: String },
    #[error("the camera info is {info_w}×{info_h} but the image is {image_w}×{image_h}")]
    SizeMismatch { info_w: u32, info_h: u32, image_w: u32, image_h: u32 },
    #[error("the clicked point is not finite")]
    ClickNotFinite,
    #[error("perception could not run: {0}")]
    Perception(String),
    #[error("an inventory round holds a read that cannot be used: {0}")]
    TagRead(String),
}

impl InputError {
    /// What kind of trouble this is, so the same trouble arriving at 30 Hz is logged once
    /// while a different one still is.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::ImageEncoding(_) => "image encoding",
            Self::ImageShape(_) => "image shape",
            Self::DepthEncoding(_) => "depth encoding",
            Self::DepthShape(_) => "depth shape",
            Self::CloudField(_) => "cloud field",
            Self::CloudShape(_) => "cloud shape",
            Self::CloudBigEndian => "cloud endianness",
            Self::CameraInfo(_) => "camera info",
            Self::Missing(_) => "missing input",
            Self::NoTransform { .. } => "transform",
            Self::ClickFrame { .. } => "click frame",
            Self::CloudFrame { .. } => "cloud frame",
            Self::SizeMismatch { .. } => "size mismatch",
            Self::ClickNotFinite => "click",
            Self::Perception(_) => "perception",
            Self::TagRead(_) => "tag read",
        }
    }
}
