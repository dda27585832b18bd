//! CiA 419 battery charger: the charger's object dictionary and the charger
//! session (PDO COB-ID pairing with the battery module, heartbeat
//! supervision, EMCY production and consumption) in its Delta-Q IC Series
//! flavour. See [`Charger`].

mod charger;
mod objects;

pub use charger::{Charger, ChargerConfig, ChargerEvent};
pub use objects::{ChargerObjects, CHARGER_DEVICE_TYPE, ERROR_HISTORY_LEN};
