//! What only the end-to-end tests in `tests/tests/` start: a real headless Chromium driven over
//! WebDriver, an MQTT broker, Home Assistant; and the module graph the walls test reads. The
//! registry, robots at work and waiting come from the test kit (`pps-test-kit`).
//!
//! Nothing here skips: when the server binary, Chromium or its driver is missing, the harness
//! panics and the test fails, saying what to install.

pub mod browser;
pub mod caretaker_view;
pub mod home_assistant;
pub mod module_graph;
pub mod mosquitto;
pub mod mqtt_watch;
pub mod test_ca;

pub use browser::{Browser, Session};
pub use home_assistant::HomeAssistant;
pub use mosquitto::Mosquitto;
pub use mqtt_watch::MqttWatch;
pub use test_ca::{ServerIdentity, TestCa};
