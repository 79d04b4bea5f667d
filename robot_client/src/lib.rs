//! The robot side of PPS-tags: the paper's perception, navigation and manipulation behind
//! hardware traits, with a deterministic simulator so all of it runs without a robot.
