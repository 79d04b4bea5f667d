//! A robot wrapped to change one capability (the simulator with a real reader in its fingers,
//! the task's robot that keeps its base's trail) passes every other capability through to the
//! robot it wraps. `forward_to!` writes those pass-through implementations, so that each
//! wrapper states only what it changes and the list of methods lives in one place.
//!
//! ```text
//! forward_to!([R: TaskRobot] Trailing<'_, R> => robot: ColorCamera, Arm, Gripper);
//! ```

macro_rules! forward_to {
    ([$($generics:tt)*] $wrapper:ty => $field:ident: MobileBase) => {
        impl<$($generics)*> $crate::hal::MobileBase for $wrapper {
            fn pose_estimate(&self) -> Result<$crate::hal::PlanarPose, $crate::hal::HalError> {
                self.$field.pose_estimate()
            }
            fn drive(&self, distance: f64) -> Result<(), $crate::hal::HalError> {
                self.$field.drive(distance)
            }
            fn turn(&self, angle: f64) -> Result<(), $crate::hal::HalError> {
                self.$field.turn(angle)
            }
            fn move_relative(
                &self,
                translation: nalgebra::Vector2<f64>,
                yaw: f64,
            ) -> Result<(), $crate::hal::HalError> {
                self.$field.move_relative(translation, yaw)
            }
        }
    };
    ([$($generics:tt)*] $wrapper:ty => $field:ident: ColorCamera) => {
        impl<$($generics)*> $crate::hal::ColorCamera for $wrapper {
            fn calibration(&self) -> $crate::hal::CameraCalibration {
                self.$field.calibration()
            }
            fn capture(
                &self,
                flash: bool,
            ) -> Result<$crate::hal::ColorImage, $crate::hal::HalError> {
                self.$field.capture(flash)
            }
        }
    };
    ([$($generics:tt)*] $wrapper:ty => $field:ident: BrightnessCamera) => {
        impl<$($generics)*> $crate::hal::BrightnessCamera for $wrapper {
            fn capture_light_source(
                &self,
                look: $crate::hal::LookDirection,
            ) -> Result<$crate::hal::GrayImage, $crate::hal::HalError> {
                self.$field.capture_light_source(look)
            }
            fn mean_intensity(
                &self,
                look: $crate::hal::LookDirection,
            ) -> Result<f64, $crate::hal::HalError> {
                self.$field.mean_intensity(look)
            }
        }
    };
    ([$($generics:tt)*] $wrapper:ty => $field:ident: TiltingLaser) => {
        impl<$($generics)*> $crate::hal::TiltingLaser for $wrapper {
            fn scan(
                &self,
                sweep: &$crate::hal::TiltSweep,
            ) -> Result<$crate::hal::PointCloud, $crate::hal::HalError> {
                self.$field.scan(sweep)
            }
        }
    };
    ([$($generics:tt)*] $wrapper:ty => $field:ident: RfidReader) => {
        impl<$($generics)*> $crate::hal::RfidReader for $wrapper {
            fn inventory(&self) -> Result<Vec<$crate::hal::TagRead>, $crate::hal::HalError> {
                self.$field.inventory()
            }
        }
    };
    ([$($generics:tt)*] $wrapper:ty => $field:ident: Carriage) => {
        impl<$($generics)*> $crate::hal::Carriage for $wrapper {
            fn height(&self) -> Result<f64, $crate::hal::HalError> {
                self.$field.height()
            }
            fn move_to_height(
                &self,
                height: f64,
                max_force: f64,
            ) -> Result<f64, $crate::hal::HalError> {
                self.$field.move_to_height(height, max_force)
            }
        }
    };
    ([$($generics:tt)*] $wrapper:ty => $field:ident: Arm) => {
        impl<$($generics)*> $crate::hal::Arm for $wrapper {
            fn extension(&self) -> Result<f64, $crate::hal::HalError> {
                self.$field.extension()
            }
            fn farthest(&self) -> f64 {
                self.$field.farthest()
            }
            fn move_to_extension(
                &self,
                extension: f64,
                max_force: f64,
            ) -> Result<f64, $crate::hal::HalError> {
                self.$field.move_to_extension(extension, max_force)
            }
        }
    };
    ([$($generics:tt)*] $wrapper:ty => $field:ident: Gripper) => {
        impl<$($generics)*> $crate::hal::Gripper for $wrapper {
            fn opening(&self) -> Result<f64, $crate::hal::HalError> {
                self.$field.opening()
            }
            fn widest(&self) -> f64 {
                self.$field.widest()
            }
            fn set_opening(&self, angle: f64, max_force: f64) -> Result<f64, $crate::hal::HalError> {
                self.$field.set_opening(angle, max_force)
            }
        }
    };
    ([$($generics:tt)*] $wrapper:ty => $field:ident: FingerForceTorque) => {
        impl<$($generics)*> $crate::hal::FingerForceTorque for $wrapper {
            fn wrench(
                &self,
                finger: $crate::hal::Finger,
            ) -> Result<$crate::hal::Wrench, $crate::hal::HalError> {
                self.$field.wrench(finger)
            }
        }
    };
    ([$($generics:tt)*] $wrapper:ty => $field:ident: PalmRange) => {
        impl<$($generics)*> $crate::hal::PalmRange for $wrapper {
            fn range(&self) -> Result<Option<f64>, $crate::hal::HalError> {
                self.$field.range()
            }
        }
    };
    ($generics:tt $wrapper:ty => $field:ident: $($capability:ident),+ $(,)?) => {
        $($crate::hal::forward_to!($generics $wrapper => $field: $capability);)+
    };
}

pub(crate) use forward_to;
