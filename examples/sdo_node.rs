//! An SDO server or client on a pipe: candump log lines in on stdin, out on
//! stdout. Used to run python-canopen against this crate (see
//! `tests/interop/sdo_interop.py`), and handy by hand.
//!
//! ```text
//! sdo_node --server --node-id N [--eds FILE [--strict-eds]]
//! sdo_node --print-eds FILE
//! sdo_node --client --node-id N [--timeout-ms T] OP...
//!     OP = read:IDX:SUB | write:IDX:SUB:HEX     (IDX and SUB in hex)
//!        | bread:IDX:SUB | bwrite:IDX:SUB:HEX   (the same by block transfer)
//! ```
//!
//! The server serves a small in-memory dictionary (listed by `--help`), or
//! with `--eds` the dictionary an EDS or DCF (CiA 306) describes, built for
//! the node id (`canopen_codec::eds`), and prints `EVENT ...` lines on
//! stderr. With `--eds` it first says on stderr, once each, what the file
//! gets wrong (line and deviation), which values it leaves out and why (a
//! data type it cannot encode, no data type, a value that does not fit),
//! and how many it serves. It serves every other value and refuses SDO
//! access to the ones left out with 06040047h (`eds::EdsDictionary`);
//! `--strict-eds` refuses such a file instead, naming them, and exits 2.
//!
//! The client waits for the first input line (any frame: the peer is
//! ready), runs the operations one after the other, prints one `RESULT ...`
//! line per operation on stderr, and exits. Time is the process's monotonic
//! clock; input timestamps are ignored.

mod support {
    pub mod bus;
}
use support::bus;

use std::process::ExitCode;

use bus::{Input, PipeBus};
use canopen_codec::eds::EdsDictionary;
use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, MemoryDictionary, ObjectDictionary};
use canopen_codec::sdo::{
    Client, ClientConfig, Collected, Server, ServerConfig, ServerEvent, UploadBuffer,
};
use canopen_codec::NodeId;

const USAGE: &str = "usage: sdo_node --server --node-id N [--eds FILE [--strict-eds]]
         --eds: serve what FILE (EDS/DCF) describes; values it cannot encode are
                named on stderr and refused with 06040047h
         --strict-eds: refuse FILE instead when it has such values
       sdo_node --print-eds FILE   (read an EDS/DCF, write it back out)
       sdo_node --client --node-id N [--timeout-ms T] OP...
         OP = read:IDX:SUB | write:IDX:SUB:HEX   (IDX, SUB in hex)
            | bread:IDX:SUB | bwrite:IDX:SUB:HEX (by block transfer)
server dictionary:
  1000:00 const u32 000F01A2      1008:00 const string
  1018:01 ro u32 00000539         2000:00..0F rw domain (<= 4096 bytes)
  2100:00 ro u32 12345678         2101:00 wo u32
  2102:00 rw u16";

fn dictionary() -> MemoryDictionary {
    let mut od = MemoryDictionary::new();
    od.insert(0x1000, 0, Access::Const, &0x000F_01A2u32.to_le_bytes());
    od.insert_variable(0x1008, 0, Access::Const, b"canopen-codec sdo_node", 64);
    od.insert(0x1018, 0, Access::Const, &[1]);
    od.insert(0x1018, 1, Access::ReadOnly, &0x539u32.to_le_bytes());
    for sub in 0..=0x0F {
        od.insert_variable(0x2000, sub, Access::ReadWrite, b"", 4096);
    }
    od.insert(0x2100, 0, Access::ReadOnly, &0x1234_5678u32.to_le_bytes());
    od.insert(0x2101, 0, Access::WriteOnly, &[0; 4]);
    od.insert(0x2102, 0, Access::ReadWrite, &[0; 2]);
    od
}

#[derive(Debug)]
enum Op {
    /// Index, sub-index, by block transfer.
    Read(u16, u8, bool),
    /// Index, sub-index, value, by block transfer.
    Write(u16, u8, Vec<u8>, bool),
}

fn parse_op(s: &str) -> Result<Op, String> {
    let parts: Vec<&str> = s.split(':').collect();
    let num = |p: &str| u32::from_str_radix(p, 16).map_err(|_| format!("bad number '{p}' in {s}"));
    let obj = |i: &str, j: &str| -> Result<(u16, u8), String> {
        let index = u16::try_from(num(i)?).map_err(|_| format!("bad index in {s}"))?;
        let sub = u8::try_from(num(j)?).map_err(|_| format!("bad sub-index in {s}"))?;
        Ok((index, sub))
    };
    match parts.as_slice() {
        [op @ ("read" | "bread"), i, j] => obj(i, j).map(|(i, j)| Op::Read(i, j, *op == "bread")),
        [op @ ("write" | "bwrite"), i, j, hex] => {
            let (i, j) = obj(i, j)?;
            if hex.len() % 2 != 0 {
                return Err(format!("odd hex digits in {s}"));
            }
            let data = (0..hex.len())
                .step_by(2)
                .map(|k| u8::from_str_radix(&hex[k..k + 2], 16))
                .collect::<Result<Vec<u8>, _>>()
                .map_err(|_| format!("bad hex in {s}"))?;
            Ok(Op::Write(i, j, data, *op == "bwrite"))
        }
        _ => Err(format!("bad operation '{s}'")),
    }
}

fn hex(data: &[u8]) -> String {
    data.iter().map(|b| format!("{b:02X}")).collect()
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut server = false;
    let mut client = false;
    let mut node = None;
    let mut timeout_ms = None;
    let mut eds = None;
    let mut strict_eds = false;
    let mut ops = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--server" => server = true,
            "--client" => client = true,
            "--node-id" => node = it.next().and_then(|v| v.parse().ok()).and_then(NodeId::new),
            "--eds" => eds = it.next().cloned(),
            "--strict-eds" => strict_eds = true,
            "--print-eds" => return print_eds(it.next().map_or("", String::as_str)),
            "--timeout-ms" => match it.next().map(|v| (v, v.parse::<u64>())) {
                Some((_, Ok(ms))) if (1..=u64::from(u32::MAX)).contains(&ms) => {
                    timeout_ms = Some(ms)
                }
                other => {
                    let v = other.map_or("", |(v, _)| v.as_str());
                    eprintln!("sdo_node: --timeout-ms: '{v}' is not 1 to 4294967295 ms\n{USAGE}");
                    return ExitCode::from(2);
                }
            },
            "-h" | "--help" => {
                eprintln!("{USAGE}");
                return ExitCode::SUCCESS;
            }
            op => match parse_op(op) {
                Ok(op) => ops.push(op),
                Err(e) => {
                    eprintln!("sdo_node: {e}\n{USAGE}");
                    return ExitCode::from(2);
                }
            },
        }
    }
    let Some(node) = node else {
        eprintln!("sdo_node: --node-id 1..=127 is required\n{USAGE}");
        return ExitCode::from(2);
    };
    if strict_eds && eds.is_none() {
        eprintln!("sdo_node: --strict-eds needs --eds FILE\n{USAGE}");
        return ExitCode::from(2);
    }
    match (server, client) {
        (true, false) => match eds {
            None => run_server(node, dictionary()),
            Some(path) => match eds_dictionary(&path, node, strict_eds) {
                Ok(od) => run_server(node, od),
                Err(e) => {
                    eprintln!("sdo_node: {path}: {e}");
                    ExitCode::from(2)
                }
            },
        },
        (false, true) => run_client(node, timeout_ms, ops),
        _ => {
            eprintln!("sdo_node: give exactly one of --server / --client\n{USAGE}");
            ExitCode::from(2)
        }
    }
}

/// Reads the EDS or DCF at `path` and prints it as `eds::write` writes it.
fn print_eds(path: &str) -> ExitCode {
    let read = std::fs::read(path).map_err(|e| e.to_string());
    match read.and_then(|b| canopen_codec::eds::parse_bytes(&b).map_err(|e| e.to_string())) {
        Ok(eds) => {
            print!("{}", canopen_codec::eds::write(&eds));
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("sdo_node: {path}: {e}");
            ExitCode::from(2)
        }
    }
}

/// The dictionary the EDS or DCF at `path` describes, for `node`. Says on
/// stderr what the file gets wrong, once each in line order, and what is
/// left out and why; with `strict`, a file with values left out is refused.
fn eds_dictionary(path: &str, node: NodeId, strict: bool) -> Result<EdsDictionary, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let eds = canopen_codec::eds::parse_bytes(&bytes).map_err(|e| e.to_string())?;
    let mut warnings = eds.warnings.clone();
    warnings.sort_by_key(|w| w.line);
    warnings.dedup();
    for w in &warnings {
        eprintln!("sdo_node: {path}: warning: {w}");
    }
    let od = eds.dictionary(node);
    let left_out = od.unserved();
    if strict && !left_out.is_empty() {
        let list: Vec<String> = left_out.iter().map(ToString::to_string).collect();
        return Err(format!(
            "--strict-eds: cannot serve {} value(s): {}",
            list.len(),
            list.join("; ")
        ));
    }
    let code = EdsDictionary::REFUSAL.to_u32();
    for u in left_out {
        eprintln!("sdo_node: {path}: left out {u}; SDO access refused with {code:08X}h");
    }
    let objects = |keep: &dyn Fn(u16, u8) -> bool| {
        eds.objects
            .values()
            .filter(|o| {
                let mut subs = o.subs.keys().copied().collect::<Vec<u8>>();
                if subs.is_empty() {
                    subs.push(0);
                }
                subs.iter().any(|&s| keep(o.index, s))
            })
            .count()
    };
    let served = objects(&|i, s| od.values().get(i, s).is_some());
    let refused = objects(&|i, s| od.refused(i, s).is_some());
    let mut summary = format!("serving {} values of {served} objects", od.values().len());
    if !left_out.is_empty() {
        summary += &format!(
            "; left out {} value(s) of {refused} object(s), refused with {code:08X}h \
             (--strict-eds refuses the file instead)",
            left_out.len()
        );
    }
    eprintln!("sdo_node: {path}: {summary}");
    Ok(od)
}

fn run_server<D: ObjectDictionary>(node: NodeId, od: D) -> ExitCode {
    let bus = PipeBus::stdin("pipe");
    let mut server = Server::new(ServerConfig::for_node(node), od);
    loop {
        match bus.recv(server.poll_timeout()) {
            Input::Frame(f, _) => server.handle_frame(bus.now(), &f),
            Input::Timeout => server.handle_timeout(bus.now()),
            Input::Closed => return ExitCode::SUCCESS,
        }
        while let Some(f) = server.poll_transmit() {
            bus.send(&f);
        }
        while let Some(e) = server.poll_event() {
            match e {
                ServerEvent::Uploaded { index, sub, len } => {
                    eprintln!("EVENT uploaded {index:04X}:{sub:02X} len {len}")
                }
                ServerEvent::Downloaded { index, sub, len } => {
                    eprintln!("EVENT downloaded {index:04X}:{sub:02X} len {len}")
                }
                ServerEvent::Aborted {
                    index,
                    sub,
                    code,
                    origin,
                } => eprintln!(
                    "EVENT aborted {index:04X}:{sub:02X} {:08X} {origin:?}",
                    code.to_u32()
                ),
                other => eprintln!("EVENT {other:?}"),
            }
        }
    }
}

fn run_client(node: NodeId, timeout_ms: Option<u64>, ops: Vec<Op>) -> ExitCode {
    let bus = PipeBus::stdin("pipe");
    let mut config = ClientConfig::for_server(node);
    if let Some(ms) = timeout_ms {
        config.timeout = std::time::Duration::from_millis(ms);
    }
    let mut client: Client<Vec<u8>> = Client::new(config);
    // Wait until the peer says it is ready (any line).
    if let Input::Closed = bus.recv(None) {
        return ExitCode::from(1);
    }
    for op in ops {
        let started = match &op {
            Op::Read(i, s, false) => client.start_upload(bus.now(), *i, *s),
            Op::Read(i, s, true) => client.start_block_upload(bus.now(), *i, *s),
            Op::Write(i, s, d, false) => client.start_download(bus.now(), *i, *s, d.clone()),
            Op::Write(i, s, d, true) => client.start_block_download(bus.now(), *i, *s, d.clone()),
        };
        if let Err(e) = started {
            eprintln!("sdo_node: {e}");
            return ExitCode::from(1);
        }
        let mut buffer = UploadBuffer::new();
        let outcome = loop {
            while let Some(f) = client.poll_transmit() {
                bus.send(&f);
            }
            let mut done = None;
            while let Some(e) = client.poll_event() {
                if let Some(c) = buffer.push(&e) {
                    done = Some(c);
                }
            }
            if let Some(d) = done {
                break d;
            }
            match bus.recv(client.poll_timeout()) {
                Input::Frame(f, _) => client.handle_frame(bus.now(), &f),
                Input::Timeout => client.handle_timeout(bus.now()),
                Input::Closed => return ExitCode::from(1),
            }
        };
        let (what, index, sub) = match op {
            Op::Read(i, s, _) => ("read", i, s),
            Op::Write(i, s, _, _) => ("write", i, s),
        };
        match outcome {
            Collected::Value(v) => eprintln!("RESULT {what} {index:04X}:{sub:02X} ok {}", hex(&v)),
            Collected::Written(n) => eprintln!("RESULT {what} {index:04X}:{sub:02X} ok len {n}"),
            Collected::Aborted { code, origin } => eprintln!(
                "RESULT {what} {index:04X}:{sub:02X} abort {:08X} {origin:?}",
                code.to_u32()
            ),
        }
        // Flush the abort frame of a failed transfer, if any.
        while let Some(f) = client.poll_transmit() {
            bus.send(&f);
        }
    }
    ExitCode::SUCCESS
}
