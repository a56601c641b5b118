//! Fuzz target: the firmware's input path for bytes from outside. The replay firmware reads
//! the setup words, then the binary log header, then 80-byte records that it decodes and
//! assembles into frames; a sensor line (nav-fsw `stream_ports`) decodes the same records.
//! Whatever the bytes: no panic, and every record that decodes re-encodes to its own bytes
//! (the decoder accepts only canonical records).
#![no_main]

use libfuzzer_sys::fuzz_target;
use nav_fsw::log_record::{decode_header, LogRecord, HEADER_SIZE, RECORD_SIZE};
use nav_fsw::replay::{FrameAssembler, FrameGrid, ReplaySetup, DEFAULT_MAX_GAP_S, SETUP_WORDS};

fuzz_target!(|data: &[u8]| {
    let mut grid = FrameGrid {
        start_time_s: 0.0,
        period_s: 0.002,
        tolerance: 0.1,
        max_gap_s: DEFAULT_MAX_GAP_S,
    };
    // The setup words (any bytes).
    if let Some(setup_bytes) = data.get(..SETUP_WORDS * 8) {
        let mut words = [0_u64; SETUP_WORDS];
        for (word, chunk) in words.iter_mut().zip(setup_bytes.chunks_exact(8)) {
            let mut bytes = [0_u8; 8];
            bytes.copy_from_slice(chunk);
            *word = u64::from_le_bytes(bytes);
        }
        if let Ok(setup) = ReplaySetup::from_words(&words) {
            assert_eq!(setup.to_words(), words);
            let _ = setup.config().validate();
            grid = setup.frame_grid();
        }
    }
    // The log header, then records, exactly as the firmware streams them.
    if let Some(header) = data.get(..HEADER_SIZE) {
        let mut fixed = [0_u8; HEADER_SIZE];
        fixed.copy_from_slice(header);
        let _ = decode_header(&fixed);
    }
    let Ok(mut assembler) = FrameAssembler::new(grid) else {
        return;
    };
    let mut rest = data;
    while rest.len() >= RECORD_SIZE {
        match LogRecord::decode_prefix(rest) {
            Ok((record, remaining)) => {
                let encoded = record.encode().expect("a decoded record encodes");
                assert_eq!(&encoded[..], &rest[..RECORD_SIZE]);
                // A refused record is skipped, as the firmware stops there.
                let _ = assembler.push(&record);
                while assembler.next_frame().is_some() {}
                rest = remaining;
            }
            Err(_) => rest = &rest[1..],
        }
    }
    assembler.finish();
    while assembler.next_frame().is_some() {}
});
