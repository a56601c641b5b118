//! Whole-scenario replay on the target: reads a sensor log written by `nav-sim`
//! (`replay-in.bin` in QEMU's working directory: the [`ReplaySetup`] words, then the binary
//! log of `docs/guide/replay-format.md`) through semihosting, runs it through nav-fsw in 2 ms frames
//! driven by the SysTick interrupt (500 Hz in QEMU's virtual time), and streams every frame's
//! output record plus its measured cost to `replay-out.bin`. Memory is static and the log is
//! streamed, so a mission of any length fits.
//!
//! Output file: per frame, [`OUTPUT_WORDS`] words of nav-fsw's output record followed by one
//! word: the frame's cost in instructions (`-icount shift=0`: one instruction = 1 ns). All
//! words little-endian u64.
//!
//! Stack file (`replay-stack.bin`): four little-endian u64 words, in bytes: the stack
//! high-water mark of the frame loop (the stack is repainted after start-up), the size of the
//! stack region, the high-water mark of start-up ([`nav_qemu::stack`]) and the size of the
//! `NavigationComputer`.
//!
//! Prints (defmt) `REPLAY frames=… worst=… overruns=… stack=…` and exits 0 when the whole log
//! was replayed with no frame overrun.
#![no_std]
#![no_main]

use cortex_m::peripheral::SYST;
use cortex_m_rt::entry;
use nav_fsw::log_record::{decode_header, LogRecord, HEADER_SIZE, RECORD_SIZE};
use nav_fsw::replay::{
    output_words, FrameAssembler, FrameGrid, ReplaySetup, OUTPUT_WORDS, SETUP_WORDS,
};
use nav_fsw::scheduler::NavigationComputer;
use nav_qemu::flight_start::start_flight_software;
use nav_qemu::frame_clock::{FrameClock, FRAME_BUDGET_INSTRUCTIONS};
use nav_qemu::host_file::{read_full, HostFile};
use nav_qemu::{exit_failure, exit_success};

/// Records read from the host per semihosting call.
const RECORDS_PER_READ: usize = 64;
/// Frames buffered per semihosting write.
const FRAMES_PER_WRITE: usize = 16;
/// Words per output frame (record + cost).
const FRAME_WORDS: usize = OUTPUT_WORDS + 1;

/// The log, streamed record by record.
struct LogStream {
    file: HostFile,
    buffer: [u8; RECORD_SIZE * RECORDS_PER_READ],
    filled: usize,
    position: usize,
}

impl LogStream {
    /// The next record; `Ok(None)` at the end of the log.
    fn next(&mut self) -> Result<Option<LogRecord>, ()> {
        if self.position >= self.filled {
            self.filled = read_full(&mut self.file, &mut self.buffer);
            self.position = 0;
            if self.filled == 0 {
                return Ok(None);
            }
        }
        let bytes = self.buffer.get(self.position..self.filled).ok_or(())?;
        match LogRecord::decode_prefix(bytes) {
            Ok((record, _)) => {
                self.position += RECORD_SIZE;
                Ok(Some(record))
            }
            Err(error) => {
                defmt::error!("replay log record: {}", error);
                Err(())
            }
        }
    }
}

/// Reads and decodes the setup. Not inlined: its byte and word buffers live in this
/// function's frame only, not while the computer is built.
#[inline(never)]
fn read_setup(file: &mut HostFile) -> Option<ReplaySetup> {
    let mut bytes = [0_u8; SETUP_WORDS * 8];
    if read_full(file, &mut bytes) != bytes.len() {
        defmt::error!("replay: setup truncated");
        return None;
    }
    let mut words = [0_u64; SETUP_WORDS];
    for (word, chunk) in words.iter_mut().zip(bytes.chunks_exact(8)) {
        let mut le = [0_u8; 8];
        le.copy_from_slice(chunk);
        *word = u64::from_le_bytes(le);
    }
    ReplaySetup::from_words(&words).ok()
}

#[entry]
fn main() -> ! {
    let Some(mut peripherals) = cortex_m::Peripherals::take() else {
        exit_failure()
    };
    // A stack overflow faults on the MPU guard instead of overwriting the statics.
    nav_qemu::stack::install_guard(&mut peripherals.MPU);
    let Some(started) = start() else {
        exit_failure()
    };
    // Start-up (reading the setup, configuration checks, building the computer) is done:
    // measure its stack peak, then repaint so the final figure is the replay loop's.
    let start_up_stack = nav_qemu::stack::usage();
    nav_qemu::stack::repaint_below_current_stack_pointer();
    replay(started, peripherals.SYST, start_up_stack)
}

/// What start-up hands to the replay loop.
struct Started {
    computer: &'static mut NavigationComputer,
    grid: FrameGrid,
    input: HostFile,
    output: HostFile,
}

/// Opens the files, reads the setup and the log header and builds the flight software. Not
/// inlined: the setup lives in this function's frame only, not in the replay loop's.
#[inline(never)]
fn start() -> Option<Started> {
    let Ok(mut input) = HostFile::open_read("replay-in.bin\0") else {
        defmt::error!("replay: cannot open replay-in.bin");
        return None;
    };
    let Ok(output) = HostFile::create("replay-out.bin\0") else {
        defmt::error!("replay: cannot create replay-out.bin");
        return None;
    };
    let Some(setup) = read_setup(&mut input) else {
        defmt::error!("replay: bad setup");
        return None;
    };
    let mut header = [0_u8; HEADER_SIZE];
    if read_full(&mut input, &mut header) != HEADER_SIZE || decode_header(&header).is_err() {
        defmt::error!("replay: bad log header");
        return None;
    }
    // The flight software's state and the I/O buffers are statics (as in an avionics image),
    // so static RAM holds the state and the stack measures only the call depth.
    let computer = start_flight_software(&setup)?;
    Some(Started {
        computer,
        grid: setup.frame_grid(),
        input,
        output,
    })
}

/// Replays the log through the computer frame by frame, writes the outputs and the stack
/// figures and exits. Its own frame (the frame assembler, the output record) is separate from
/// the start-up's, so start-up's stack peak is the computer's construction, not the loop's
/// buffers.
#[inline(never)]
fn replay(started: Started, systick: SYST, start_up_stack: nav_qemu::stack::StackUsage) -> ! {
    let Started {
        computer,
        grid,
        input,
        mut output,
    } = started;
    computer.set_frame_budget(FRAME_BUDGET_INSTRUCTIONS);
    let Some(log) = cortex_m::singleton!(: LogStream = LogStream {
        file: input,
        buffer: [0; RECORD_SIZE * RECORDS_PER_READ],
        filled: 0,
        position: 0,
    }) else {
        exit_failure()
    };
    let Ok(mut assembler) = FrameAssembler::new(grid) else {
        defmt::error!("replay: bad frame grid");
        exit_failure()
    };
    let Some(out_words) = cortex_m::singleton!(: [u64; FRAME_WORDS * FRAMES_PER_WRITE] = [0; FRAME_WORDS * FRAMES_PER_WRITE])
    else {
        exit_failure()
    };
    let mut out_frames = 0_usize;
    let Some(out_bytes) = cortex_m::singleton!(
        : [u8; FRAME_WORDS * FRAMES_PER_WRITE * 8] = [0; FRAME_WORDS * FRAMES_PER_WRITE * 8]
    ) else {
        exit_failure()
    };
    let mut frames = 0_u32;
    let mut clock = FrameClock::start(systick);
    loop {
        // The next frame from the log (outside the measured frame).
        let next = assembler.next_frame_from(|| match log.next() {
            Ok(record) => record,
            Err(()) => exit_failure(),
        });
        let mut ports = match next {
            Ok(Some(ports)) => ports,
            Ok(None) => break,
            Err(error) => {
                defmt::error!("replay: log refused: {}", error);
                exit_failure()
            }
        };
        let (telemetry, cost) = clock.run_frame(|| ports.run(computer));
        computer.report_frame_cost(cost);
        let record = output_words(&telemetry, computer, &assembler.counts());
        let base = out_frames * FRAME_WORDS;
        if let Some(slot) = out_words.get_mut(base..base + FRAME_WORDS) {
            let (record_slot, cost_slot) = slot.split_at_mut(OUTPUT_WORDS);
            record_slot.copy_from_slice(&record);
            if let Some(word) = cost_slot.first_mut() {
                *word = u64::from(cost);
            }
        }
        out_frames += 1;
        frames += 1;
        if out_frames == FRAMES_PER_WRITE {
            write_frames(&mut output, out_words, out_frames, out_bytes);
            out_frames = 0;
        }
    }
    write_frames(&mut output, out_words, out_frames, out_bytes);
    let health = computer.health();
    let stack = nav_qemu::stack::usage();
    defmt::println!(
        "REPLAY frames={=u32} worst={=u32} overruns={=u32} budget={=u32} stack={=u32}/{=u32} bytes start-up stack={=u32} bytes",
        frames,
        computer.worst_frame_cost(),
        health.frame_overruns,
        FRAME_BUDGET_INSTRUCTIONS,
        stack.high_water_bytes,
        stack.region_bytes,
        start_up_stack.high_water_bytes
    );
    drop(output);
    let mut stack_bytes = [0_u8; 32];
    let figures = [
        u64::from(stack.high_water_bytes),
        u64::from(stack.region_bytes),
        u64::from(start_up_stack.high_water_bytes),
        // The computer's memory (the blocks this build carries), for the results.
        u64::try_from(core::mem::size_of::<NavigationComputer>()).unwrap_or(u64::MAX),
    ];
    for (chunk, figure) in stack_bytes.chunks_exact_mut(8).zip(figures) {
        chunk.copy_from_slice(&figure.to_le_bytes());
    }
    let written =
        HostFile::create("replay-stack.bin\0").and_then(|mut file| file.write_all(&stack_bytes));
    if written.is_err() {
        defmt::error!("replay: cannot write replay-stack.bin");
        exit_failure()
    }
    if frames > 0 && health.frame_overruns == 0 {
        exit_success()
    } else {
        exit_failure()
    }
}

/// Writes the first `frames` frames of `words` to `output` as little-endian bytes (through
/// `bytes`); a failed write ends the replay with a failure.
fn write_frames(output: &mut HostFile, words: &[u64], frames: usize, bytes: &mut [u8]) {
    let words = words.get(..frames * FRAME_WORDS).unwrap_or(&[]);
    for (chunk, word) in bytes.chunks_exact_mut(8).zip(words) {
        chunk.copy_from_slice(&word.to_le_bytes());
    }
    if output
        .write_all(bytes.get(..words.len() * 8).unwrap_or(&[]))
        .is_err()
    {
        defmt::error!("replay: output write failed");
        exit_failure()
    }
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic on target");
    exit_failure()
}
