//! How much memory this process may still have, to refuse work that
//! cannot fit before doing it, with a message, rather than be killed or
//! abort on an allocation half way through.

use anyhow::{bail, Result};

/// Bytes this process can still allocate: the least of the machine's
/// available memory (`MemAvailable`), its control group's room and its
/// address-space limit (`ulimit -v`). `None` where none of them is known.
pub fn available() -> Option<u64> {
    [meminfo_available(), cgroup_room(), address_space_room()].into_iter().flatten().min()
}

/// Refuse `what` when it needs more than [`available`].
pub fn check(what: &str, needed: u64) -> Result<()> {
    match available() {
        Some(have) if needed > have => bail!(
            "{what} needs about {} of memory; this process can have {} (the least of the machine's \
             available memory, its control group's limit and `ulimit -v`)",
            gib(needed),
            gib(have)
        ),
        _ => Ok(()),
    }
}

/// `n` bytes as "2.5 GB", or "21 MB" below a gigabyte.
pub fn gib(n: u64) -> String {
    if n < 1 << 30 {
        format!("{} MB", n.div_ceil(1 << 20))
    } else {
        format!("{:.1} GB", n as f64 / (1u64 << 30) as f64)
    }
}

fn meminfo_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

fn cgroup_room() -> Option<u64> {
    let read = |f: &str| std::fs::read_to_string(format!("/sys/fs/cgroup/{f}")).ok();
    let max: u64 = read("memory.max")?.trim().parse().ok()?;
    let current: u64 = read("memory.current").and_then(|c| c.trim().parse().ok()).unwrap_or(0);
    Some(max.saturating_sub(current))
}

/// The soft address-space limit less what is mapped now.
fn address_space_room() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits.lines().find(|l| l.starts_with("Max address space"))?;
    let soft: u64 = line["Max address space".len()..].split_whitespace().next()?.parse().ok()?;
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let vm_kb: u64 =
        status.lines().find(|l| l.starts_with("VmSize:"))?.split_whitespace().nth(1)?.parse().ok()?;
    Some(soft.saturating_sub(vm_kb * 1024))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_is_known_on_linux_and_absurd_needs_are_refused() {
        if cfg!(target_os = "linux") {
            assert!(available().is_some_and(|n| n > 1 << 20));
            let e = check("a render of 10^18 pixels", 1 << 62).unwrap_err().to_string();
            assert!(e.contains("needs about 4294967296.0 GB"), "{e}");
        }
        assert!(check("nothing", 0).is_ok());
    }
}
