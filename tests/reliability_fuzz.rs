//! Reliability suite (issue 16), crafted-file fuzz pass: every loader of a file a user hands
//! xylem (npy volumes, PNG photos and knot markers, the TOML configs, model folders and
//! checkpoints, NRRD and Mitsuba volumes, run records) is fed a fixed number of mutated
//! files made from valid ones: bit flips, truncation, random bytes, structure-aware header
//! edits (numbers replaced by huge, negative or NaN values, keys duplicated, lines dropped,
//! PNG chunks rewritten with their CRC fixed). The property is the issue's: the loader
//! returns Ok or a clear Err: it never panics (`catch_unwind`), never takes more than 2 s
//! on one file, and never asks for an allocation out of proportion to the file (a
//! 300-byte file must not reserve 400 MB). Seeded (xylem's own `Rng`), so every run tries
//! the same files; a failure names the case and keeps its input in the scratch folder.

mod common;
mod reliability_support;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use xylem::Image2;
use xylem::device::DeviceKind;
use xylem::export::Values;
use xylem::field::FieldConfig;
use xylem::fit::FitConfig;
use xylem::frame::Face;
use xylem::io::npy::{read_npy, read_volume, write_npy};
use xylem::io::{Provenance, load_gray, load_rgb, save_png};
use xylem::loss::{LossConfig, Texture2dConfig};
use xylem::nca::TrainConfig;
use xylem::nca::fit_source::FitRecord;
use xylem::nca::model_dir::{ModelMeta, TrainedModel};
use xylem::nca::tensors::to_vec;
use xylem::nca::train::Trainer;
use xylem::procedural::SpeciesConfig;
use xylem::render::RenderConfig;
use xylem::rng::Rng;
use xylem::sample::{Needs, Sample};

use reliability_support::{copy_dir, repo, tiny_data, tiny_model};
use xylem::config::ConfigFile;

// ---------------------------------------------------------------------------------------
// Allocation watch: the largest single request made on the current thread.

struct Watch;

thread_local! {
    static LARGEST: Cell<usize> = const { Cell::new(0) };
}

fn note(size: usize) {
    let _ = LARGEST.try_with(|l| {
        if size > l.get() {
            l.set(size);
        }
    });
}

/// Above this a request is refused outright (the test then aborts with "memory allocation
/// of N bytes failed" instead of swapping the machine to death).
const REFUSE: usize = 4 << 30;

unsafe impl GlobalAlloc for Watch {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        if layout.size() > REFUSE {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        if layout.size() > REFUSE {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        if new_size > REFUSE {
            return std::ptr::null_mut();
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Watch = Watch;

// ---------------------------------------------------------------------------------------
// Panics are caught; the hook keeps the message and location for the report.

thread_local! {
    static LAST_PANIC: std::cell::RefCell<String> = const { std::cell::RefCell::new(String::new()) };
}

fn quiet_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if std::thread::current()
                .name()
                .is_some_and(|n| n.starts_with("fuzz-"))
            {
                let text = format!("{info}");
                let _ = LAST_PANIC.try_with(|p| *p.borrow_mut() = text);
            } else {
                default(info);
            }
        }));
    });
}

// ---------------------------------------------------------------------------------------
// Mutations.

/// What a seed file is, for the structure-aware edits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// TOML or CSV text.
    Text,
    /// `.npy`: binary with a text header dictionary.
    Npy,
    Png,
    /// NRRD: a text header, a blank line, raw floats.
    Nrrd,
    /// Other binary (Mitsuba .vol, burnpack).
    Binary,
}

const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "-0.0",
    "nan",
    "inf",
    "-inf",
    "1e39",
    "-1e39",
    "1e30",
    "1e-45",
    "3.5",
    "255",
    "65536",
    "4294967296",
    "9223372036854775807",
    "18446744073709551615",
    "18446744073709551616",
    "4611686018427387904",
    "99999999999999999999999",
    "\"x\"",
    "[]",
    "[1, 2, 3, 4, 5]",
    "true",
    "{}",
];

const LINES: &[&str] = &[
    "[extra]",
    "bogus = 1",
    "seed = -5",
    "grid = [100000, 100000, 100000]",
    "size = 0",
    "[[knots]]",
    "'shape': (4611686018427387904, 4, 1, 1)",
    "sizes: 1073741824 1073741824 4 4",
    "type: double",
    "= = =",
    "\u{0}\u{1}",
];

fn pick<'a, T>(rng: &mut Rng, items: &'a [T]) -> &'a T {
    &items[rng.below(items.len())]
}

/// Byte ranges of number-like tokens (digits with sign, point, exponent) in `bytes`.
fn number_spans(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_digit() {
            let mut start = i;
            if start > 0 && bytes[start - 1] == b'-' {
                start -= 1;
            }
            while i < bytes.len()
                && (bytes[i].is_ascii_digit() || matches!(bytes[i], b'.' | b'e' | b'E' | b'_'))
            {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

/// The line spans of `bytes` (without their newline).
fn line_spans(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = 0;
    for (i, &b) in bytes.iter().enumerate() {
        if b == b'\n' {
            spans.push((start, i));
            start = i + 1;
        }
    }
    if start < bytes.len() {
        spans.push((start, bytes.len()));
    }
    spans
}

/// Where a text header ends (the whole file for text).
fn header_end(kind: Kind, bytes: &[u8]) -> usize {
    match kind {
        Kind::Text => bytes.len(),
        Kind::Npy => {
            if bytes.len() >= 10 {
                (10 + u16::from_le_bytes([bytes[8], bytes[9]]) as usize).min(bytes.len())
            } else {
                bytes.len()
            }
        }
        Kind::Nrrd => bytes
            .windows(2)
            .position(|w| w == b"\n\n")
            .map_or(bytes.len(), |p| p + 1),
        _ => 0,
    }
}

/// Replaces one number of the text header with a hostile value.
fn edit_number(rng: &mut Rng, bytes: &mut Vec<u8>, end: usize) -> bool {
    let spans: Vec<_> = number_spans(&bytes[..end]);
    if spans.is_empty() {
        return false;
    }
    let (a, b) = *pick(rng, &spans);
    let new = pick(rng, NUMBERS).as_bytes().to_vec();
    bytes.splice(a..b, new);
    true
}

/// Duplicates, drops, swaps a header line or inserts a foreign one.
fn edit_line(rng: &mut Rng, bytes: &mut Vec<u8>, end: usize) -> bool {
    let lines = line_spans(&bytes[..end]);
    if lines.is_empty() {
        return false;
    }
    let (a, b) = *pick(rng, &lines);
    match rng.below(4) {
        0 => {
            let mut copy = bytes[a..b].to_vec();
            copy.push(b'\n');
            bytes.splice(a..a, copy);
        }
        1 => {
            let stop = (b + 1).min(bytes.len());
            bytes.drain(a..stop);
        }
        2 => {
            let (c, d) = *pick(rng, &lines);
            if (c, d) != (a, b) {
                let first = bytes[a..b].to_vec();
                let second = bytes[c..d].to_vec();
                if a < c {
                    bytes.splice(c..d, first);
                    bytes.splice(a..b, second);
                } else {
                    bytes.splice(a..b, second);
                    bytes.splice(c..d, first);
                }
            }
        }
        _ => {
            let mut line = pick(rng, LINES).as_bytes().to_vec();
            line.push(b'\n');
            bytes.splice(a..a, line);
        }
    }
    true
}

/// Appends to or shortens an array of the text (`[1, 2]` -> `[1, 2, 2]` or `[1]`).
fn edit_array(rng: &mut Rng, bytes: &mut Vec<u8>, end: usize) -> bool {
    let closes: Vec<usize> = (0..end).filter(|&i| bytes[i] == b']').collect();
    if closes.is_empty() {
        return false;
    }
    let at = *pick(rng, &closes);
    if rng.below(2) == 0 {
        let extra = format!(", {}", pick(rng, NUMBERS));
        bytes.splice(at..at, extra.into_bytes());
    } else if let Some(comma) = bytes[..at].iter().rposition(|&b| b == b',') {
        bytes.drain(comma..at);
    }
    true
}

/// (offset of the length field, data length) of every chunk of a PNG.
fn png_chunks(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut chunks = Vec::new();
    let mut at = 8;
    while at + 12 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        if at + 12 + len > bytes.len() {
            break;
        }
        chunks.push((at, len));
        at += 12 + len;
    }
    chunks
}

/// Rewrites a PNG chunk's content (IHDR sizes, depth and colour type above all) and fixes
/// its CRC, so the decoder gets past the checksum to the values themselves.
fn edit_png(rng: &mut Rng, bytes: &mut [u8]) -> bool {
    let chunks = png_chunks(bytes);
    if chunks.is_empty() {
        return false;
    }
    let (at, len) = if rng.below(2) == 0 {
        chunks[0] // IHDR
    } else {
        *pick(rng, &chunks)
    };
    if len == 0 {
        return false;
    }
    let data = at + 8;
    let is_ihdr = &bytes[at + 4..at + 8] == b"IHDR";
    if is_ihdr && rng.below(3) > 0 {
        let sizes: [u32; 10] = [0, 1, 2, 15, 16, 4096, 12000, 65535, 0x7fff_ffff, u32::MAX];
        match rng.below(4) {
            0 => bytes[data..data + 4].copy_from_slice(&pick(rng, &sizes).to_be_bytes()),
            1 => bytes[data + 4..data + 8].copy_from_slice(&pick(rng, &sizes).to_be_bytes()),
            2 => bytes[data + 8] = *pick(rng, &[1u8, 2, 4, 8, 16, 3, 0, 255]),
            _ => bytes[data + 9] = *pick(rng, &[0u8, 2, 3, 4, 6, 1, 7, 255]),
        }
    } else {
        flip_bits(rng, &mut bytes[data..data + len], 4);
    }
    let crc = reliability_support::crc32(&bytes[at + 4..data + len]);
    bytes[data + len..data + len + 4].copy_from_slice(&crc.to_be_bytes());
    true
}

/// Flips one to `most` random bits of `bytes` (false when it is empty).
fn flip_bits(rng: &mut Rng, bytes: &mut [u8], most: usize) -> bool {
    if bytes.is_empty() {
        return false;
    }
    for _ in 0..1 + rng.below(most) {
        let i = rng.below(bytes.len());
        bytes[i] ^= 1 << rng.below(8);
    }
    true
}

/// A random non-empty range inside `len` bytes, at most `most` long (None when `len` is 0).
fn random_span(rng: &mut Rng, len: usize, most: usize) -> Option<std::ops::Range<usize>> {
    if len == 0 {
        return None;
    }
    let start = rng.below(len);
    Some(start..(start + 1 + rng.below(most)).min(len))
}

/// Cuts the file at a random length (possibly to nothing).
fn cut_at_random(rng: &mut Rng, bytes: &mut Vec<u8>) -> bool {
    let keep = rng.below(bytes.len() + 1);
    bytes.truncate(keep);
    true
}

/// Overwrites four bytes with an interesting word (zero, extremes, f32 inf and NaN).
fn write_word(rng: &mut Rng, bytes: &mut [u8]) -> bool {
    if bytes.len() < 4 {
        return false;
    }
    let i = rng.below(bytes.len() - 3);
    let words: [u32; 8] = [
        0,
        1,
        0x7fff_ffff,
        0xffff_ffff,
        0x8000_0000,
        0x0001_0000,
        0x7f80_0000, // f32 inf
        0x7fc0_0000, // f32 NaN
    ];
    bytes[i..i + 4].copy_from_slice(&pick(rng, &words).to_le_bytes());
    true
}

/// `n` random bytes.
fn random_bytes(rng: &mut Rng, n: usize) -> Vec<u8> {
    (0..n).map(|_| rng.next_u64() as u8).collect()
}

/// Inserts 1 to 64 random bytes somewhere.
fn insert_noise(rng: &mut Rng, bytes: &mut Vec<u8>) -> bool {
    let at = rng.below(bytes.len() + 1);
    let n = 1 + rng.below(64);
    let noise = random_bytes(rng, n);
    bytes.splice(at..at, noise);
    true
}

/// Repeats a block of up to 256 bytes after itself (duplicated structure, longer data).
fn repeat_block(rng: &mut Rng, bytes: &mut Vec<u8>) -> bool {
    let Some(span) = random_span(rng, bytes.len(), 256) else {
        return false;
    };
    let block = bytes[span.clone()].to_vec();
    bytes.splice(span.end..span.end, block);
    true
}

/// A whole random file of up to 255 bytes.
fn random_file(rng: &mut Rng) -> Vec<u8> {
    let n = rng.below(256);
    random_bytes(rng, n)
}

/// Text-like characters, so a scribbled text file stays text.
const PRINTABLE: &[u8] = b" -.,=[]\"'0123456789aezx{}()#\n";

/// Overwrites up to 8 bytes with printable characters.
fn scribble(rng: &mut Rng, bytes: &mut [u8]) -> bool {
    let Some(span) = random_span(rng, bytes.len(), 8) else {
        return false;
    };
    for b in &mut bytes[span] {
        *b = PRINTABLE[rng.below(PRINTABLE.len())];
    }
    true
}

/// One mutated copy of `seed`.
fn mutate(rng: &mut Rng, seed: &[u8], kind: Kind) -> Vec<u8> {
    let mut bytes = seed.to_vec();
    let rounds = 1 + rng.below(3);
    for _ in 0..rounds {
        let end = header_end(kind, &bytes);
        let structured = match kind {
            Kind::Text | Kind::Npy | Kind::Nrrd => 6,
            Kind::Png => 4,
            Kind::Binary => 0,
        };
        let choice = rng.below(10 + structured);
        let done = match choice {
            0..=2 => flip_bits(rng, &mut bytes, 8),
            3 | 4 => cut_at_random(rng, &mut bytes),
            5 => write_word(rng, &mut bytes),
            6 => insert_noise(rng, &mut bytes),
            7 => repeat_block(rng, &mut bytes),
            8 => {
                bytes = random_file(rng);
                true
            }
            9 => scribble(rng, &mut bytes),
            _ => match kind {
                Kind::Png => edit_png(rng, &mut bytes),
                _ => match choice - 10 {
                    0..=2 => edit_number(rng, &mut bytes, end),
                    3..=4 => edit_line(rng, &mut bytes, end),
                    _ => edit_array(rng, &mut bytes, end),
                },
            },
        };
        if !done {
            bytes.push(rng.next_u64() as u8);
        }
    }
    // Text headers of npy files state their own length; keep it right half of the time so
    // the parser, not the length check, meets the edit.
    if kind == Kind::Npy && bytes.len() >= 10 && rng.below(2) == 0 {
        let data = seed.len() - header_end(Kind::Npy, seed);
        let header = bytes.len().saturating_sub(10 + data);
        if header <= u16::MAX as usize {
            bytes[8..10].copy_from_slice(&(header as u16).to_le_bytes());
        }
    }
    bytes
}

// ---------------------------------------------------------------------------------------
// The harness.

/// Per-case limits of the property.
const CASE_TIME: Duration = Duration::from_secs(2);
/// Largest single allocation allowed for a case: a fixed allowance for the loaders' own
/// work (model records, decoders' buffers) plus what the file's size can justify: deflate
/// holds at most ~1032 decoded bytes per file byte, and a decoded byte becomes at most 12
/// bytes of float RGB (a grey pixel expanded to three f32).
fn allocation_allowance(input_len: usize) -> usize {
    (64 << 20) + 1100 * 12 * input_len
}

/// `XYLEM_FUZZ_SCALE=N` multiplies every loader's case count (a deeper run by hand or in a
/// nightly job; the default 1 keeps the suite within seconds). Same seeds, so a scaled run
/// starts with the default run's cases.
fn scale() -> usize {
    std::env::var("XYLEM_FUZZ_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .filter(|&n| n >= 1)
        .unwrap_or(1)
}

struct Target {
    name: &'static str,
    /// What the loader is given: the mutated file, or the folder holding it. Every error
    /// message must name it.
    given: PathBuf,
    kind: Kind,
    seeds: Vec<Vec<u8>>,
    /// Where each mutated file is written before the loader runs.
    file: PathBuf,
    cases: usize,
}

impl Target {
    /// A target whose mutated `file` is what the loader is given.
    fn file(
        name: &'static str,
        kind: Kind,
        seeds: Vec<Vec<u8>>,
        file: PathBuf,
        cases: usize,
    ) -> Self {
        Target {
            name,
            given: file.clone(),
            kind,
            seeds,
            file,
            cases,
        }
    }

    /// A target whose mutated file is `file` inside `folder`, the folder the loader is given.
    fn in_folder(
        name: &'static str,
        kind: Kind,
        seeds: Vec<Vec<u8>>,
        folder: &Path,
        file: impl AsRef<Path>,
        cases: usize,
    ) -> Self {
        Target {
            given: folder.to_path_buf(),
            ..Target::file(name, kind, seeds, folder.join(file), cases)
        }
    }
}

/// What a loader made of one file.
enum Verdict {
    Loaded,
    /// The error's message.
    Refused(String),
    /// Loaded, but the value breaks an invariant (a silent wrong result).
    Wrong(String),
}

/// A loader's result as a verdict; `check` looks for a broken invariant in a loaded value.
fn verdict<T>(result: xylem::Result<T>, check: impl FnOnce(&T) -> Option<String>) -> Verdict {
    match result {
        Ok(value) => match check(&value) {
            None => Verdict::Loaded,
            Some(problem) => Verdict::Wrong(problem),
        },
        Err(e) => Verdict::Refused(e.to_string()),
    }
}

/// Any loaded value is fine.
fn any<T>(_: &T) -> Option<String> {
    None
}

/// A loaded volume must be one `Volume::from_data` accepts: sizes > 0, data of their length.
fn sane_volume(v: &xylem::Volume) -> Option<String> {
    xylem::Volume::from_data(v.dims, v.channels, v.data.clone())
        .err()
        .map(|e| format!("loaded an impossible volume: {e}"))
}

/// A loaded image has pixels, the channels asked for and data of its size.
fn sane_image(channels: usize) -> impl Fn(&Image2) -> Option<String> {
    move |img| {
        let ok = img.width > 0
            && img.height > 0
            && img.channels == channels
            && img.data.len() == img.width * img.height * channels
            && img.data.iter().all(|v| (0.0..=1.0).contains(v));
        (!ok).then(|| {
            format!(
                "loaded an impossible image {}x{}x{} with {} values",
                img.width,
                img.height,
                img.channels,
                img.data.len()
            )
        })
    }
}

struct CaseReport {
    case: usize,
    bytes: Vec<u8>,
    result: std::result::Result<Verdict, String>,
    seconds: f64,
    largest: usize,
}

/// Runs `cases` mutated files through `load` (given what the target gives the loader: the
/// file, or its folder) on a worker thread; returns the number of Ok and Err results. Panics
/// (with every failing case) on a panic, hang or absurd allocation.
fn fuzz<F>(scratch: &Path, target: Target, seed: u64, load: F) -> (usize, usize)
where
    F: Fn(&Path) -> Verdict + Send + 'static,
{
    quiet_panics();
    let (tx, rx) = mpsc::channel::<CaseReport>();
    let name = target.name;
    let names = show(&target.given);
    assert!(!target.seeds.is_empty(), "{name}: no seed files");
    let cases = target.cases * scale();
    let worker = std::thread::Builder::new()
        .name(format!("fuzz-{name}"))
        .spawn(move || {
            let mut rng = Rng::new(seed);
            for case in 0..cases {
                let base = &target.seeds[case % target.seeds.len()];
                let bytes = mutate(&mut rng, base, target.kind);
                std::fs::write(&target.file, &bytes).expect("write the fuzz input");
                LARGEST.with(|l| l.set(0));
                let started = Instant::now();
                let result = std::panic::catch_unwind(AssertUnwindSafe(|| load(&target.given)));
                let seconds = started.elapsed().as_secs_f64();
                let largest = LARGEST.with(|l| l.get());
                let result = match result {
                    Ok(v) => Ok(v),
                    Err(_) => Err(LAST_PANIC.with(|p| p.borrow().clone())),
                };
                let report = CaseReport {
                    case,
                    bytes,
                    result,
                    seconds,
                    largest,
                };
                if tx.send(report).is_err() {
                    return;
                }
            }
        })
        .expect("spawn the fuzz worker");
    let (mut oks, mut errs) = (0, 0);
    let mut failures = Vec::new();
    let started = Instant::now();
    let mut slowest = 0.0f64;
    let mut largest = 0usize;
    for expected in 0..cases {
        let report = match rx.recv_timeout(Duration::from_secs(30)) {
            Ok(r) => r,
            Err(_) => {
                failures.push(format!("case {expected}: hang (no answer in 30 s)"));
                break;
            }
        };
        slowest = slowest.max(report.seconds);
        largest = largest.max(report.largest);
        let keep = |what: &str, failures: &mut Vec<String>| {
            let path = scratch.join(format!("{name}-case{}.bin", report.case));
            std::fs::write(&path, &report.bytes).unwrap();
            failures.push(format!(
                "case {} ({} bytes, kept as {}): {what}",
                report.case,
                report.bytes.len(),
                path.display()
            ));
        };
        match &report.result {
            Err(panic) => keep(&format!("panic: {panic}"), &mut failures),
            Ok(Verdict::Loaded) => oks += 1,
            Ok(Verdict::Refused(message)) => {
                errs += 1;
                if !message.contains(&names) {
                    keep(
                        &format!("the error does not name {names}: {message}"),
                        &mut failures,
                    );
                }
            }
            Ok(Verdict::Wrong(problem)) => {
                keep(&format!("silent wrong result: {problem}"), &mut failures)
            }
        }
        if report.seconds > CASE_TIME.as_secs_f64() {
            keep(
                &format!("took {:.1} s (limit 2 s)", report.seconds),
                &mut failures,
            );
        }
        if report.largest > allocation_allowance(report.bytes.len()) {
            keep(
                &format!(
                    "asked for {} MB at once for a {}-byte file",
                    report.largest >> 20,
                    report.bytes.len()
                ),
                &mut failures,
            );
        }
    }
    let _ = worker.join();
    println!(
        "fuzz {name}: {cases} cases in {:.1} s, {oks} Ok, {errs} Err, slowest {:.3} s, largest allocation {} KB",
        started.elapsed().as_secs_f64(),
        slowest,
        largest >> 10
    );
    assert!(
        failures.is_empty(),
        "fuzz {name}: {} failing cases:\n{}",
        failures.len(),
        failures.join("\n")
    );
    (oks, errs)
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn noise_image(w: usize, h: usize, channels: usize, seed: u64) -> Image2 {
    let mut rng = Rng::new(seed);
    let data = (0..w * h * channels).map(|_| rng.uniform()).collect();
    Image2::from_data(w, h, channels, data).unwrap()
}

// ---------------------------------------------------------------------------------------
// The loaders.

fn show(path: &Path) -> String {
    path.display().to_string()
}

#[test]
fn npy_readers_survive_crafted_files() {
    let dir = reliability_support::scratch("fuzz-npy");
    let mut seeds = Vec::new();
    for (i, shape) in [
        vec![2usize, 3, 2, 3],
        vec![1, 1, 1, 1],
        vec![5],
        vec![2, 3, 2, 2, 2],
        vec![4, 4, 4, 3],
    ]
    .into_iter()
    .enumerate()
    {
        let n: usize = shape.iter().product();
        let data: Vec<f32> = (0..n).map(|v| v as f32 * 0.01).collect();
        let path = dir.join(format!("seed{i}.npy"));
        write_npy(&path, &shape, &data).unwrap();
        seeds.push(read(&path));
    }
    let file = dir.join("case.npy");
    let target = |name, cases| Target::file(name, Kind::Npy, seeds.clone(), file.clone(), cases);
    fuzz(&dir, target("npy-volume", 2000), 11, |f| {
        verdict(read_volume(f), sane_volume)
    });
    fuzz(&dir, target("npy-array", 1000), 12, |f| {
        verdict(read_npy(f), |(shape, data)| {
            let n = shape.iter().try_fold(1usize, |a, &d| a.checked_mul(d));
            (n != Some(data.len())).then(|| format!("shape {shape:?} with {} values", data.len()))
        })
    });
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn png_loaders_survive_crafted_files() {
    let dir = reliability_support::scratch("fuzz-png");
    let mut seeds = Vec::new();
    for (i, (w, h, c)) in [(16, 16, 3), (16, 16, 1), (4, 4, 4), (1, 1, 3), (3, 17, 3)]
        .into_iter()
        .enumerate()
    {
        let path = dir.join(format!("seed{i}.png"));
        save_png(&noise_image(w, h, c, i as u64), &path).unwrap();
        seeds.push(read(&path));
    }
    // 16 bits per channel and grey + alpha, written by the image crate itself.
    let wide = image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(8, 8, |x, y| {
        image::Rgb([(x * 8000) as u16, (y * 8000) as u16, 300])
    });
    let path = dir.join("seed16.png");
    wide.save(&path).unwrap();
    seeds.push(read(&path));
    let la = image::ImageBuffer::<image::LumaA<u8>, _>::from_fn(8, 8, |x, y| {
        image::LumaA([(x * 30) as u8, (y * 30) as u8])
    });
    let path = dir.join("seedla.png");
    la.save(&path).unwrap();
    seeds.push(read(&path));

    let file = dir.join("case.png");
    let target = |name, cases| Target::file(name, Kind::Png, seeds.clone(), file.clone(), cases);
    fuzz(&dir, target("png-rgb", 1500), 21, |f| {
        verdict(load_rgb(f), sane_image(3))
    });
    fuzz(&dir, target("png-gray", 1000), 22, |f| {
        verdict(load_gray(f), sane_image(1))
    });
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sample folder whose knot marker image (and one photo) is the mutated file: the marker
/// search and the photo checks behind `Sample::load`.
#[test]
fn sample_folders_survive_crafted_photos_and_knot_markers() {
    let dir = reliability_support::scratch("fuzz-sample");
    let sample = dir.join("S");
    reliability_support::write_tiny_sample(&sample, 16);
    let mut marker = Image2::filled(16, 16, 1, 1.0);
    marker.pixel_mut(3, 4)[0] = 186.0 / 255.0;
    marker.pixel_mut(9, 12)[0] = 178.0 / 255.0;
    save_png(&marker, &dir.join("marker.png")).unwrap();
    let seeds = vec![
        read(&dir.join("marker.png")),
        read(&sample.join("A_col.png")),
    ];
    let needs = Needs {
        photos: true,
        arl: true,
    };
    fuzz(
        &dir,
        Target::in_folder(
            "sample-knot-marker",
            Kind::Png,
            seeds.clone(),
            &sample,
            "C_knot.png",
            600,
        ),
        31,
        move |s| {
            verdict(Sample::load(s, &Face::ALL, needs), |sample| {
                let n = sample.knot_markers.len();
                (n > 6 * 8).then(|| format!("{n} knot markers (at most 8 per face)"))
            })
        },
    );
    std::fs::remove_file(sample.join("C_knot.png")).unwrap();
    fuzz(
        &dir,
        Target::in_folder("sample-photo", Kind::Png, seeds, &sample, "B_col.png", 400),
        32,
        move |s| {
            verdict(Sample::load(s, &[Face::B], needs), |sample| {
                (sample.size < 16).then(|| format!("a {} px sample", sample.size))
            })
        },
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The seeds of a config loader: shipped files (with their comments) and their parsed,
/// re-serialised form (every default written out).
fn config_seeds<T: serde::Serialize>(
    files: &[&str],
    parse: impl Fn(&Path) -> xylem::Result<T>,
) -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    for f in files {
        let path = repo(f);
        seeds.push(read(&path));
        let value = parse(&path).unwrap_or_else(|e| panic!("{f}: {e}"));
        seeds.push(xylem::config::to_toml(&value).unwrap().into_bytes());
    }
    seeds
}

/// Fuzzes a config loader. A config it accepts must survive the round trip xylem makes
/// with it: written back as TOML (the config copy beside every output) and loaded again,
/// it is accepted and equal.
fn fuzz_config<T: serde::Serialize + PartialEq + std::fmt::Debug + 'static>(
    dir: &Path,
    name: &'static str,
    files: &[&str],
    cases: usize,
    seed: u64,
    load: fn(&Path) -> xylem::Result<T>,
) {
    let file = dir.join(format!("{name}.toml"));
    let copy = dir.join(format!("{name}-copy.toml"));
    fuzz(
        dir,
        Target::file(name, Kind::Text, config_seeds(files, load), file, cases),
        seed,
        move |f| {
            verdict(load(f), |value| {
                let text = xylem::config::to_toml(value).ok()?;
                std::fs::write(&copy, &text).unwrap();
                match load(&copy) {
                    Ok(again) if &again == value => None,
                    Ok(again) => Some(format!("written back, reads as {again:?}")),
                    Err(e) => Some(format!("its config copy is refused: {e}")),
                }
            })
        },
    );
}

#[test]
fn config_loaders_survive_crafted_files() {
    let dir = reliability_support::scratch("fuzz-config");
    fuzz_config(
        &dir,
        "field-config",
        &[
            "configs/fields/distorted.toml",
            "configs/fields/knots.toml",
            "configs/fields/knot_dead.toml",
            "configs/fields/minimal.toml",
        ],
        1000,
        41,
        FieldConfig::load,
    );
    fuzz_config(
        &dir,
        "species-config",
        &[
            "configs/species/oak.toml",
            "configs/species/softwood.toml",
            "configs/species/burl.toml",
        ],
        800,
        42,
        SpeciesConfig::load,
    );
    fuzz_config(
        &dir,
        "nca-config",
        &[
            "configs/nca/default.toml",
            "configs/nca/quick.toml",
            "configs/nca/quality.toml",
        ],
        1000,
        43,
        TrainConfig::load,
    );
    fuzz_config(
        &dir,
        "fit-config",
        &["configs/fit/default.toml"],
        800,
        44,
        FitConfig::load,
    );
    fuzz_config(
        &dir,
        "render-config",
        &["configs/render/default.toml"],
        800,
        45,
        RenderConfig::load,
    );
    fuzz_config(
        &dir,
        "loss-config",
        &["configs/loss/default.toml"],
        800,
        46,
        LossConfig::load,
    );
    // texture2d's config.toml, as it writes it.
    let t2d = dir.join("t2d-seed.toml");
    xylem::config::write_config_copy(
        &t2d,
        &Texture2dConfig::with_loss(LossConfig::default_config()),
        "test",
    )
    .unwrap();
    let seeds = vec![read(&t2d)];
    fuzz(
        &dir,
        Target::file(
            "texture2d-config",
            Kind::Text,
            seeds,
            dir.join("t2d.toml"),
            500,
        ),
        47,
        |f| verdict(Texture2dConfig::load(f), any),
    );
    // A run record (`RUN/run.toml`) compared with a fresh one.
    let record = Provenance::default()
        .with("faces", "A,B,C")
        .with("sample", "/data/S")
        .with("sample_hash", "0123456789abcdef")
        .with("synth_steps", "90");
    let rec = dir.join("run-seed.toml");
    record.check_or_record(&rec, false).unwrap();
    let seeds = vec![read(&rec)];
    fuzz(
        &dir,
        Target::file("run-record", Kind::Text, seeds, dir.join("run.toml"), 400),
        48,
        move |f| verdict(record.check_or_record(f, true), any),
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn nrrd_and_mitsuba_readers_survive_crafted_files() {
    let dir = reliability_support::scratch("fuzz-export");
    let mut nrrd = Vec::new();
    let mut vol = Vec::new();
    for (i, (dims, c)) in [([2usize, 3, 2], 3usize), ([1, 1, 1], 1), ([3, 2, 4], 2)]
        .into_iter()
        .enumerate()
    {
        let n = dims.iter().product::<usize>() * c;
        let v = xylem::Volume::from_data(dims, c, (0..n).map(|x| x as f32 / n as f32).collect())
            .unwrap();
        let p = dir.join(format!("seed{i}.nrrd"));
        xylem::export::nrrd::write_nrrd(&p, &v, Values::Data).unwrap();
        nrrd.push(read(&p));
        let p = dir.join(format!("seed{i}.vol"));
        xylem::export::mitsuba::write_vol(&p, &v).unwrap();
        vol.push(read(&p));
    }
    fuzz(
        &dir,
        Target::file("nrrd", Kind::Nrrd, nrrd, dir.join("case.nrrd"), 1500),
        51,
        |f| verdict(xylem::export::nrrd::read_nrrd(f), sane_volume),
    );
    fuzz(
        &dir,
        Target::file("mitsuba-vol", Kind::Binary, vol, dir.join("case.vol"), 1500),
        52,
        |f| verdict(xylem::export::mitsuba::read_vol(f), |(v, _)| sane_volume(v)),
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A loaded model must be one a synthesis can use: finite weights of its architecture.
fn sane_model(m: &TrainedModel) -> Option<String> {
    let finite = |v: xylem::Result<Vec<f32>>| v.is_ok_and(|v| v.iter().all(|x| x.is_finite()));
    let ok = m.model.matches(&m.meta.spec)
        && finite(to_vec(m.model.w1.val()))
        && finite(to_vec(m.model.b1.val()))
        && finite(to_vec(m.model.w2.val()));
    (!ok).then(|| "weights that are not finite or not of model.toml's architecture".to_string())
}

#[test]
fn model_and_checkpoint_loaders_survive_crafted_files() {
    let dir = reliability_support::scratch("fuzz-model");
    let (sample_dir, cfg) = tiny_model(&dir);
    let model = dir.join("model");
    let device = DeviceKind::Flex.device();
    TrainedModel::load(&model, &device).unwrap();

    // model.toml (ModelMeta::load, then the whole folder).
    let meta_dir = dir.join("meta");
    copy_dir(&model, &meta_dir);
    let seeds = vec![read(&model.join("model.toml"))];
    fuzz(
        &dir,
        Target::in_folder(
            "model-toml",
            Kind::Text,
            seeds,
            &meta_dir,
            "model.toml",
            700,
        ),
        61,
        |d| match ModelMeta::load(d) {
            Err(e) => Verdict::Refused(e.to_string()),
            Ok(_) => verdict(
                TrainedModel::load(d, &DeviceKind::Flex.device()),
                sane_model,
            ),
        },
    );

    // model.bpk with the hash check on (any change is refused) and off (a model.toml
    // without weights_hash, as written before the hash existed: burn's record parser and
    // the architecture check meet the bytes).
    let seeds = vec![read(&model.join("model.bpk"))];
    let hashed_dir = dir.join("bpk-hashed");
    copy_dir(&model, &hashed_dir);
    let original = read(&model.join("model.bpk"));
    fuzz(
        &dir,
        Target::in_folder(
            "model-bpk-hashed",
            Kind::Binary,
            seeds.clone(),
            &hashed_dir,
            "model.bpk",
            300,
        ),
        62,
        move |d| {
            let changed = read(&d.join("model.bpk")) != original;
            verdict(TrainedModel::load(d, &DeviceKind::Flex.device()), |_| {
                changed.then(|| "damaged weights loaded despite weights_hash".to_string())
            })
        },
    );
    let bpk_dir = dir.join("bpk");
    copy_dir(&model, &bpk_dir);
    let meta = std::fs::read_to_string(model.join("model.toml")).unwrap();
    let unhashed: String = meta
        .lines()
        .filter(|l| !l.starts_with("weights_hash"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(bpk_dir.join("model.toml"), unhashed).unwrap();
    fuzz(
        &dir,
        Target::in_folder("model-bpk", Kind::Binary, seeds, &bpk_dir, "model.bpk", 700),
        63,
        |d| {
            // Without the hash, flipped weight bytes load (the hash is what catches them);
            // the invariant is only that what loads has the architecture of model.toml.
            verdict(TrainedModel::load(d, &DeviceKind::Flex.device()), |m| {
                (!m.model.matches(&m.meta.spec)).then(|| "weights of another shape".to_string())
            })
        },
    );

    // fit.toml of the model folder (FitRecord::load).
    let seeds = vec![read(&model.join("fit.toml"))];
    fuzz(
        &dir,
        Target::file(
            "model-fit-toml",
            Kind::Text,
            seeds,
            dir.join("fit.toml"),
            400,
        ),
        64,
        |f| verdict(FitRecord::load(f, None), any),
    );

    // The checkpoint: progress.toml, pool.npy, loss.csv and optimiser.bpk, each restored
    // into a trainer of the tiny config.
    let checkpoint = model.join("checkpoint");
    for (i, (file, kind, cases)) in [
        ("progress.toml", Kind::Text, 400),
        ("pool.npy", Kind::Npy, 250),
        ("loss.csv", Kind::Text, 300),
        ("optimiser.bpk", Kind::Binary, 300),
    ]
    .into_iter()
    .enumerate()
    {
        let root = dir.join(format!("ckpt{i}"));
        copy_dir(&checkpoint, &root.join("checkpoint"));
        let seeds = vec![read(&checkpoint.join(file))];
        let (s, c) = (sample_dir.clone(), cfg.clone());
        let name: &'static str = Box::leak(format!("checkpoint-{file}").into_boxed_str());
        let loader = move |root: &Path| {
            // The trainer lives on the worker thread (built on first use).
            thread_local! {
                static TRAINER: std::cell::RefCell<Option<Trainer>> =
                    const { std::cell::RefCell::new(None) };
            }
            TRAINER.with(|t| {
                let mut t = t.borrow_mut();
                if t.is_none() {
                    let data = tiny_data(&s, &c);
                    *t = Some(Trainer::new(&c, &data, DeviceKind::Flex).unwrap());
                }
                let trainer = t.as_mut().unwrap();
                verdict(xylem::nca::train::snapshot::load(root, trainer), |rows| {
                    (rows.len() < trainer.iteration).then(|| {
                        format!(
                            "{} log rows for a checkpoint at iteration {}",
                            rows.len(),
                            trainer.iteration
                        )
                    })
                })
            })
        };
        fuzz(
            &dir,
            Target::in_folder(
                name,
                kind,
                seeds,
                &root,
                Path::new("checkpoint").join(file),
                cases,
            ),
            65 + i as u64,
            loader,
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
