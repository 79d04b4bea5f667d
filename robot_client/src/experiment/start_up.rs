//! Start-up: the robot's class, and so the body the simulator builds for it, comes from the
//! registry, as a real robot of a class would learn its entries' overrides.

use crate::registry::{RegistryClient, RegistryError};
use crate::sim::SimBody;

/// What the robot does when it starts: learns its class from the registry, so the simulator
/// builds that class's body, and reads the registry's tags into its cache. Without the registry
/// it goes on with the record and the entries it kept from the last time.
pub async fn start_up(registry: &RegistryClient) -> anyhow::Result<SimBody> {
    let record = match registry.robot_record().await {
        Ok(record) => record,
        Err(error @ RegistryError::Unreachable(_)) => anyhow::bail!(
            "{error}; this robot has never reached it, so it knows neither its class nor any tag"
        ),
        Err(error) if error.status() == Some(404) => anyhow::bail!(
            "robot {0} is not registered: an admin registers it, with its class, by \
             PUT /api/v1/robots/{0}",
            registry.robot()
        ),
        Err(error) => return Err(error.into()),
    };
    let known = SimBody::ALL.map(SimBody::class).join(" or ");
    let Some(class) = record.class.as_ref().map(|c| c.as_str()) else {
        anyhow::bail!(
            "robot {0} has no class yet: an admin sets one ({known}) by PUT /api/v1/robots/{0}",
            registry.robot()
        );
    };
    let Some(body) = SimBody::for_class(class) else {
        anyhow::bail!(
            "robot {} has class `{class}`; the simulator builds robots of class {known}",
            registry.robot()
        );
    };
    match registry.sync_entries().await {
        Ok(_) => {}
        Err(error @ RegistryError::Unreachable(_)) => {
            tracing::warn!(
                "{error}; going on with the {} entries kept",
                registry.known_entries().len()
            )
        }
        Err(error) => return Err(error.into()),
    }
    Ok(body)
}
