//! Rough timings of the SQLite store on this machine's disk:
//! `cargo run --release -p frep-store --example store_timing [DIR]`.
//!
//! Measures durable saves (each one committed and synced), model loads,
//! history pages, a diff of two versions of a 2,000-line source, and log
//! reads. Prints medians; asserts nothing (a measurement, not a test).

use std::time::Instant;

use frep_store::{
    CreateModel, HistoryPage, NewVersion, SqliteStore, Store, StoreError, StoreLimits,
};

fn median_us(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn time<T>(n: usize, mut f: impl FnMut(usize) -> Result<T, StoreError>) -> Result<f64, StoreError> {
    let mut samples = Vec::with_capacity(n);
    for i in 0..n {
        let t = Instant::now();
        f(i)?;
        samples.push(t.elapsed().as_secs_f64() * 1e6);
    }
    Ok(median_us(samples))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = match std::env::args().nth(1) {
        Some(d) => std::path::PathBuf::from(d),
        None => std::env::temp_dir(),
    };
    let path = dir.join(format!("frep-store-timing-{}.db", std::process::id()));
    let store = SqliteStore::open(&path, StoreLimits::default())?;
    let source: String = (0..2000)
        .map(|i| format!("  t{i} = hfSphere(x, c, {i}.5);\n"))
        .collect();
    let id = store
        .create_model(
            "bench",
            CreateModel {
                name: "timing".into(),
                source: source.clone(),
                params: vec![1.0; 8],
                message: String::new(),
            },
        )?
        .value
        .model
        .id;
    let save = time(200, |i| {
        let mut s = source.clone();
        s.push_str(&format!("-- {i}\n"));
        store.save_version(
            &id,
            "bench",
            NewVersion {
                source: s,
                ..NewVersion::default()
            },
        )
    })?;
    let load = time(500, |_| store.get_model(&id))?;
    let hist = time(200, |_| store.history(&id, HistoryPage::default()))?;
    let diff = time(50, |i| store.diff(&id, 1, 2 + (i as u32 % 150)))?;
    let log = time(500, |_| store.changes(&id, 100, Some(100)))?;
    println!(
        "source {} bytes, {} versions",
        source.len(),
        store.get_model(&id)?.model.latest
    );
    println!("save (durable)   {save:9.0} µs median");
    println!("get_model        {load:9.0} µs median");
    println!("history (200)    {hist:9.0} µs median");
    println!("diff 2000 lines  {diff:9.0} µs median");
    println!("changes (100)    {log:9.0} µs median");
    store.close()?;
    for ext in ["", "-wal", "-shm"] {
        let p = format!("{}{ext}", path.display());
        let _ = std::fs::remove_file(p);
    }
    Ok(())
}
