//! An SDO client and server on a [`Sim`] (1 ms latency, names [`CLIENT`] and
//! [`SERVER`]), and the upload helper.

use std::ops::{Deref, DerefMut};

use canopen_codec::od::{MemoryDictionary, ObjectDictionary};
use canopen_codec::sdo::{Client, ClientConfig, ClientEvent, Server, ServerConfig, ServerEvent};
use canopen_codec::NodeId;

use super::sim::{bus, Bus, Handle};

pub const CLIENT: &str = "client";
pub const SERVER: &str = "server";

/// The value collected from a client's `UploadData` events, in order.
pub fn uploaded<D: AsRef<[u8]> + 'static>(sim: &Bus, client: Handle<Client<D>>) -> Vec<u8> {
    let mut v = Vec::new();
    for (_, e) in sim.events(client) {
        if let ClientEvent::UploadData { offset, data, .. } = e {
            assert_eq!(*offset, v.len(), "upload pieces out of order");
            v.extend_from_slice(data.as_slice());
        }
    }
    v
}

/// A client for node `node` and that node's server, on one bus. Derefs to
/// the [`Bus`].
pub struct SdoPair<D: ObjectDictionary + 'static = MemoryDictionary> {
    pub sim: Bus,
    pub client: Handle<Client<Vec<u8>>>,
    pub server: Handle<Server<D>>,
}

impl<D: ObjectDictionary + 'static> SdoPair<D> {
    pub fn new(node: u8, od: D) -> Self {
        let node = NodeId::new(node).unwrap();
        let mut sim = bus(1_000);
        let client = sim.add(CLIENT, Client::new(ClientConfig::for_server(node)));
        let server = sim.add(SERVER, Server::new(ServerConfig::for_node(node), od));
        SdoPair {
            sim,
            client,
            server,
        }
    }

    pub fn client_events(&self) -> Vec<ClientEvent> {
        self.sim.event_list(self.client)
    }

    pub fn server_events(&self) -> Vec<ServerEvent> {
        self.sim.event_list(self.server)
    }

    /// The value collected from the client's upload events.
    pub fn uploaded(&self) -> Vec<u8> {
        uploaded(&self.sim, self.client)
    }

    /// Runs a command on the client at the current time (then flushes it).
    pub fn with_client<R>(
        &mut self,
        command: impl FnOnce(&mut Client<Vec<u8>>, canopen_codec::Timestamp) -> R,
    ) -> R {
        let c = self.client;
        self.sim.with(c, command).unwrap()
    }

    pub fn client(&self) -> &Client<Vec<u8>> {
        self.sim.machine(self.client).unwrap()
    }

    pub fn server(&self) -> &Server<D> {
        self.sim.machine(self.server).unwrap()
    }

    /// The server's dictionary.
    pub fn od(&self) -> &D {
        self.sim.machine(self.server).unwrap().od()
    }
}

impl<D: ObjectDictionary + 'static> Deref for SdoPair<D> {
    type Target = Bus;
    fn deref(&self) -> &Bus {
        &self.sim
    }
}

impl<D: ObjectDictionary + 'static> DerefMut for SdoPair<D> {
    fn deref_mut(&mut self) -> &mut Bus {
        &mut self.sim
    }
}
