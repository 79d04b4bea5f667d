//! The end-to-end tests, one binary: each module was a test file of its own (linking one
//! binary for each cost more than running them). nextest still runs each test in a process of
//! its own.

mod accessibility;
mod browser;
mod browser_learned_size;
mod browser_purpose;
mod browser_tasks;
mod caretaker_first_hour;
mod crash;
mod credentials;
mod disk_full;
mod docs;
mod floods;
mod home_assistant;
mod home_assistant_mqtt;
mod home_assistant_mqtts;
mod home_assistant_replicas;
mod hostile_input;
mod locked_database;
mod plain_words;
mod task_floods;
mod walls;
mod work;
