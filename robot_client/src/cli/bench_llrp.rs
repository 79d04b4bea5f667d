//! `pps-robot bench-llrp`: how fast RO_ACCESS_REPORTs decode (on one core), and, given a reader
//! (`--llrp HOST[:PORT]`, e.g. llrpkit's emulator), what one inventory round costs beyond its
//! own duration. Run it optimised: `cargo run --release -p pps-robot -- bench-llrp`.

use std::hint::black_box;
use std::time::{Duration, Instant};

use clap::Args;

use crate::hal::RfidReader;
use crate::rfid::llrp::messages::Message;
use crate::rfid::llrp::params::report::{EpcData, FirstSeen, TagReportData};
use crate::rfid::llrp::{LlrpReader, LlrpSettings};

#[derive(Debug, Args)]
pub struct BenchLlrpArgs {
    /// Tag reports per RO_ACCESS_REPORT message.
    #[arg(long, default_value_t = 100)]
    pub per_message: usize,
    /// How long to decode, seconds (0.1 to 3600).
    #[arg(long, default_value_t = 2.0, value_parser = seconds)]
    pub seconds: f64,
    /// Also time inventory rounds on this reader.
    #[arg(long)]
    pub llrp: Option<String>,
    /// Rounds to time on --llrp.
    #[arg(long, default_value_t = 50)]
    pub rounds: usize,
    /// Each round's duration, milliseconds (10 to 60000).
    #[arg(long, default_value_t = 100, value_parser = super::rfid::round_ms)]
    pub round_ms: u64,
}

pub fn run(args: &BenchLlrpArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.per_message > 0 && args.rounds > 0,
        "--per-message and --rounds must be at least 1"
    );
    // What a busy reader sends: EPC-96, antenna, RSSI, first-seen time and ROSpec id per read.
    let tags = (0..args.per_message)
        .map(|i| TagReportData {
            antenna_id: Some(1 + (i % 4) as u16),
            peak_rssi: Some(-40 - (i % 30) as i8),
            first_seen: Some(FirstSeen::Utc(1_764_000_000_000_000 + i as u64)),
            rospec_id: Some(0x5050),
            ..TagReportData::of(EpcData::from_bytes(&(i as u128).to_be_bytes()[4..]))
        })
        .collect();
    let bytes = Message::RoAccessReport { tags }.encode(1);
    let budget = Duration::from_secs_f64(args.seconds);
    let started = Instant::now();
    let mut reports = 0usize;
    while started.elapsed() < budget {
        for _ in 0..100 {
            if let Ok((_, Message::RoAccessReport { tags })) = Message::decode(black_box(&bytes)) {
                reports += tags.len();
            }
        }
    }
    let rate = reports as f64 / started.elapsed().as_secs_f64();
    println!(
        "RO_ACCESS_REPORT decoding: {:.2} M tag reports/s ({} per message, {} bytes each)",
        rate / 1e6,
        args.per_message,
        bytes.len()
    );
    if let Some(address) = &args.llrp {
        let round = Duration::from_millis(args.round_ms);
        let connect = Instant::now();
        let reader = LlrpReader::connect(LlrpSettings { round, ..LlrpSettings::new(address) })?;
        let set_up = connect.elapsed();
        let mut overheads = Vec::with_capacity(args.rounds);
        let mut reads = 0;
        for _ in 0..args.rounds {
            let t = Instant::now();
            reads += reader.inventory()?.len();
            overheads.push((t.elapsed().as_secs_f64() - round.as_secs_f64()) * 1000.0);
        }
        drop(reader);
        overheads.sort_by(f64::total_cmp);
        println!(
            "{address}: connect and set up {:.1} ms; {} rounds of {} ms, {reads} reads; overhead \
             beyond the round: median {:.1} ms, max {:.1} ms",
            set_up.as_secs_f64() * 1000.0,
            args.rounds,
            args.round_ms,
            overheads[overheads.len() / 2],
            overheads[overheads.len() - 1]
        );
    }
    Ok(())
}

/// How long to decode: a tenth of a second to an hour.
fn seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if (0.1..=3600.0).contains(&s) => Ok(s),
        _ => Err(format!("{text:?} is not 0.1 to 3600 seconds")),
    }
}
