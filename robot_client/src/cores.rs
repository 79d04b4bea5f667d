//! The cores the perception chain splits its larger steps over.
//!
//! The chain projects the cloud, checks the robot's clearance and crops the volume of interest
//! (beside the tag search) on rayon's pool, in blocks joined in the cloud's order, so its
//! answers are those of one core. A thread that merely asks the pool for that work sleeps
//! while the pool's own threads do it, and on a virtual machine's two cores a pool thread
//! wakes tens of microseconds late, several times a look. [`work_on_this_thread`] makes the
//! calling thread one of the pool's workers instead: it does its share itself, and only the
//! other half waits for a second core.

/// Makes the calling thread a worker of rayon's global pool, beside as many others as the
/// machine has cores (or `RAYON_NUM_THREADS` asks for) less this one. For the thread that runs
/// the perception chain, before its first look: the command lines' main thread.
///
/// Does nothing when the pool is already running (another thread asked it for work first, or
/// this was called before): the chain then runs on that pool, just as right.
pub fn work_on_this_thread() {
    // The only error is a pool that already exists, and that pool serves as well.
    let _ = rayon::ThreadPoolBuilder::new().use_current_thread().build_global();
}
