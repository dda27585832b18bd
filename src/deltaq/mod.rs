//! Delta-Q IC Series charger: alarm and fault table, the 1003h byte-order
//! quirk, manufacturer objects and the EMCY-consumer reaction policy.
