//! Whole-scenario replay over serial lines, as a flight computer hears its sensors: the IMU,
//! the star tracker and the GNSS receiver each send the log's 80-byte records on their own
//! CMSDK UART ([`nav_qemu::cmsdk_uart`]); nav-fsw's [`RecordReader`] finds the records in
//! each byte stream (resynchronising after corrupt bytes), [`ArrivalMerge`] puts the three
//! lines back into arrival order, and the frame assembler and the computer run as in the
//! `replay` firmware, one frame per SysTick interrupt (500 Hz of QEMU's virtual time). No
//! semihosting file is read.
//!
//! | UART | direction | content |
//! |---|---|---|
//! | 0, ground link | in | the [`ReplaySetup`] words, then the byte length of each sensor line (three u64: IMU, star, GNSS), then each telemetry packet kind's rate (`PacketKind::ALL` order, frames) |
//! | 0, ground link | out | per frame the `nav_fsw::replay::OUTPUT_WORDS` words of the output record and its cost (instructions); then [`LINES_MAGIC`] and four counters per line (records, resynchronisation bytes, wrong kind, read errors) |
//! | 1 | in | the IMU's records |
//! | 2 | in | the star tracker's records |
//! | 3 | in | the GNSS receiver's records |
//! | 4, telemetry | out | per frame the telemetry packets due (`nav_fsw::telemetry_packets`, CCSDS space packets) |
//!
//! All words little-endian u64. The line lengths let the replay tell a line that has ended
//! from one whose next byte is still on its way. Prints (defmt) `UART REPLAY frames=… worst=…`
//! and exits 0 when every line was replayed with no frame overrun.
#![no_std]
#![no_main]

use core::convert::Infallible;

use cortex_m_rt::entry;
use embedded_io::{ErrorType, Read, ReadReady, Write};
use nav_fsw::replay::{output_words, FrameAssembler, ReplaySetup, SETUP_WORDS};
use nav_fsw::stream_merge::{ArrivalMerge, FiniteStream, LineSource};
use nav_fsw::stream_ports::{RecordReader, StreamCounters};
use nav_fsw::telemetry_packets::{
    PacketEncoder, PacketRates, MAX_FRAME_PACKET_BYTES, PACKET_KIND_COUNT,
};
use nav_qemu::cmsdk_uart::CmsdkUart;
use nav_qemu::flight_start::start_flight_software;
use nav_qemu::frame_clock::{FrameClock, FRAME_BUDGET_INSTRUCTIONS};
use nav_qemu::{exit_failure, exit_success};

/// The ground link's UART.
const GROUND_UART: usize = 0;
/// The telemetry packets' UART.
const TELEMETRY_UART: usize = 4;
/// The sensor lines' UARTs: IMU, star tracker, GNSS receiver.
const SENSOR_UARTS: [usize; 3] = [1, 2, 3];
/// First word of the line counters after the last frame (`"NAVLINES"` little-endian).
const LINES_MAGIC: u64 = u64::from_le_bytes(*b"NAVLINES");

/// A sensor line being played back: its UART and the bytes still to come.
struct PlayedLine {
    uart: CmsdkUart,
    remaining_bytes: u64,
}

impl ErrorType for PlayedLine {
    type Error = Infallible;
}

impl Read for PlayedLine {
    fn read(&mut self, buffer: &mut [u8]) -> Result<usize, Infallible> {
        let allowed = usize::try_from(self.remaining_bytes).unwrap_or(usize::MAX);
        let Some(slot) = buffer.get_mut(..allowed.min(buffer.len())) else {
            return Ok(0);
        };
        if slot.is_empty() {
            return Ok(0);
        }
        let read = self.uart.read(slot)?;
        self.remaining_bytes -= read as u64;
        Ok(read)
    }
}

impl ReadReady for PlayedLine {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(self.remaining_bytes > 0 && self.uart.read_ready()?)
    }
}

impl FiniteStream for PlayedLine {
    fn exhausted(&self) -> bool {
        self.remaining_bytes == 0
    }
}

type Line = LineSource<PlayedLine>;

/// Reads `N` little-endian words from the ground link.
fn read_words<const N: usize>(ground: &mut CmsdkUart) -> Option<[u64; N]> {
    let mut words = [0_u64; N];
    for word in &mut words {
        let mut bytes = [0_u8; 8];
        ground.read_exact(&mut bytes).ok()?;
        *word = u64::from_le_bytes(bytes);
    }
    Some(words)
}

fn write_words(ground: &mut CmsdkUart, words: &[u64]) {
    for word in words {
        let _ = ground.write_all(&word.to_le_bytes());
    }
}

fn sensor_line(index: usize, remaining_bytes: u64) -> Option<Line> {
    let uart = CmsdkUart::take(index)?;
    Some(LineSource(RecordReader::new(PlayedLine {
        uart,
        remaining_bytes,
    })))
}

#[entry]
fn main() -> ! {
    let Some(mut peripherals) = cortex_m::Peripherals::take() else {
        exit_failure()
    };
    nav_qemu::stack::install_guard(&mut peripherals.MPU);
    let (Some(mut ground), Some(mut telemetry_link)) = (
        CmsdkUart::take(GROUND_UART),
        CmsdkUart::take(TELEMETRY_UART),
    ) else {
        exit_failure()
    };
    let Some(setup) = read_words::<SETUP_WORDS>(&mut ground)
        .and_then(|words| ReplaySetup::from_words(&words).ok())
    else {
        defmt::error!("uart replay: bad setup");
        exit_failure()
    };
    let Some([imu_bytes, star_bytes, gnss_bytes]) = read_words::<3>(&mut ground) else {
        exit_failure()
    };
    let Some(rates) = read_words::<PACKET_KIND_COUNT>(&mut ground).and_then(packet_rates) else {
        defmt::error!("uart replay: telemetry packet rates refused");
        exit_failure()
    };
    let [imu_uart, star_uart, gnss_uart] = SENSOR_UARTS;
    let (Some(imu), Some(star), Some(gnss)) = (
        sensor_line(imu_uart, imu_bytes),
        sensor_line(star_uart, star_bytes),
        sensor_line(gnss_uart, gnss_bytes),
    ) else {
        exit_failure()
    };
    let Some(computer) = start_flight_software(&setup) else {
        exit_failure()
    };
    computer.set_frame_budget(FRAME_BUDGET_INSTRUCTIONS);
    let Ok(mut assembler) = FrameAssembler::new(setup.frame_grid()) else {
        defmt::error!("uart replay: bad frame grid");
        exit_failure()
    };
    let mut lines = ArrivalMerge::new(imu, star, gnss);
    let mut packets = PacketEncoder::new(rates);
    let mut packet_buffer = [0_u8; MAX_FRAME_PACKET_BYTES];
    let mut clock = FrameClock::start(peripherals.SYST);
    let mut frames = 0_u32;
    loop {
        let mut ports = match assembler.next_frame_from(|| lines.next_record()) {
            Ok(Some(ports)) => ports,
            Ok(None) => break,
            Err(error) => {
                defmt::error!("uart replay: record refused: {}", error);
                exit_failure()
            }
        };
        let (telemetry, cost) = clock.run_frame(|| ports.run(computer));
        computer.report_frame_cost(cost);
        let record = output_words(&telemetry, computer, &assembler.counts());
        write_words(&mut ground, &record);
        write_words(&mut ground, &[u64::from(cost)]);
        match packets.encode_frame(&record, &mut packet_buffer) {
            Ok(length) => {
                let _ = telemetry_link.write_all(packet_buffer.get(..length).unwrap_or_default());
            }
            Err(error) => {
                defmt::error!("uart replay: telemetry packets: {}", error);
                exit_failure()
            }
        }
        frames += 1;
    }
    let (imu, star, gnss) = lines.sources();
    write_words(&mut ground, &[LINES_MAGIC]);
    for counters in [imu.counters(), star.counters(), gnss.counters()] {
        write_words(&mut ground, &counter_words(&counters));
    }
    let _ = ground.flush();
    let _ = telemetry_link.flush();
    let health = computer.health();
    defmt::println!(
        "UART REPLAY frames={=u32} worst={=u32} overruns={=u32} star resync bytes={=u32}",
        frames,
        computer.worst_frame_cost(),
        health.frame_overruns,
        star.counters().resync_bytes
    );
    if frames > 0 && health.frame_overruns == 0 {
        exit_success()
    } else {
        exit_failure()
    }
}

/// The packet rates from the ground link's words (`None` for one the encoder refuses).
fn packet_rates(words: [u64; PACKET_KIND_COUNT]) -> Option<PacketRates> {
    let mut every_frames = [0_u32; PACKET_KIND_COUNT];
    for (slot, word) in every_frames.iter_mut().zip(words) {
        *slot = u32::try_from(word).ok()?;
    }
    PacketRates::new(every_frames).ok()
}

fn counter_words(counters: &StreamCounters) -> [u64; 4] {
    [
        u64::from(counters.records),
        u64::from(counters.resync_bytes),
        u64::from(counters.wrong_kind),
        u64::from(counters.read_errors),
    ]
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic on target");
    exit_failure()
}
