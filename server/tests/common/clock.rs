//! The registry's time in the tests' hands: leases, expiry, throttles and sessions run out when
//! a test moves the clock, not while it waits.

use std::time::Duration;

use super::TestServer;

impl TestServer {
    /// Moves the registry's clock forward by `by`, as if that much time had passed.
    pub fn advance(&self, by: Duration) {
        self.clock.advance(by);
    }

    /// The registry's time now.
    pub fn now(&self) -> time::OffsetDateTime {
        self.clock.now()
    }
}
