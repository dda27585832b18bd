//! CiA 418 battery-module profile: objects, statuses, units, packed strings.
