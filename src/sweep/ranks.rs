//! What an MPI launcher tells a process (compiled with or without the `mpi` feature):
//! whether it is one of several ranks, and how many threads each rank's rayon pool gets.
//!
//! Thread rule of a rank ([`threads_per_rank`]), first that applies:
//! 1. `RAYON_NUM_THREADS` when set to a whole number >= 1 (rayon reads it itself);
//! 2. the cores the process may run on, when the launcher bound it to fewer cores than the
//!    node has (`mpirun` binds each rank to one core by default when it starts 2 ranks or
//!    fewer; `--map-by slot:PE=4` binds 4): the binding already splits the node;
//! 3. the node's cores divided by the ranks on the node (`OMPI_COMM_WORLD_LOCAL_SIZE`,
//!    MPICH's `MPI_LOCALNRANKS`), at least 1.

/// Variables by which launchers give the number of ranks (OpenMPI, then MPICH / Hydra
/// and Intel MPI).
const WORLD_SIZE_VARS: [&str; 2] = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"];
/// Variables by which launchers give the number of ranks on this node.
const LOCAL_SIZE_VARS: [&str; 2] = ["OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"];

fn env_count(vars: &[&str]) -> Option<usize> {
    vars.iter()
        .find_map(|v| std::env::var(v).ok())
        .and_then(|s| s.trim().parse::<usize>().ok())
        .filter(|&n| n >= 1)
}

/// The number of ranks an MPI launcher started, when this process is one of them.
pub fn launcher_world_size() -> Option<usize> {
    env_count(&WORLD_SIZE_VARS)
}

/// Threads of one rank and the reason (for the log).
pub fn threads_per_rank(
    rayon_env: Option<&str>,
    local_ranks: Option<usize>,
    usable_cores: usize,
    node_cores: usize,
) -> (usize, String) {
    if let Some(n) = rayon_env
        .and_then(|s| s.trim().parse::<usize>().ok())
        .filter(|&n| n >= 1)
    {
        return (n, format!("RAYON_NUM_THREADS={n}"));
    }
    let usable = usable_cores.max(1);
    if usable < node_cores {
        return (
            usable,
            format!("bound by the launcher to {usable} of the node's {node_cores} cores"),
        );
    }
    let local = local_ranks.unwrap_or(1).max(1);
    let n = (usable / local).max(1);
    (
        n,
        format!("{usable} cores / {local} ranks on the node = {n}"),
    )
}

/// Cores of the node that are online (`/sys/devices/system/cpu/online`, e.g. `0-3,8`);
/// `None` where that file is missing or unreadable.
pub fn node_cores() -> Option<usize> {
    let text = std::fs::read_to_string("/sys/devices/system/cpu/online").ok()?;
    parse_cpu_list(text.trim())
}

/// Counts a Linux CPU list `0-3,8,10-11`.
fn parse_cpu_list(text: &str) -> Option<usize> {
    let mut count = 0;
    for part in text.split(',').filter(|p| !p.is_empty()) {
        match part.split_once('-') {
            Some((a, b)) => {
                let (a, b) = (a.parse::<usize>().ok()?, b.parse::<usize>().ok()?);
                if b < a {
                    return None;
                }
                count += b - a + 1;
            }
            None => {
                part.parse::<usize>().ok()?;
                count += 1;
            }
        }
    }
    (count > 0).then_some(count)
}

/// Sizes rayon's global pool by the rule of the module docs; returns the thread count and
/// the reason. Call before anything uses rayon.
pub fn set_rank_threads() -> anyhow::Result<(usize, String)> {
    let usable = std::thread::available_parallelism().map_or(1, |n| n.get());
    let node = node_cores().unwrap_or(usable);
    let rayon_env = std::env::var("RAYON_NUM_THREADS").ok();
    let (n, why) = threads_per_rank(
        rayon_env.as_deref(),
        env_count(&LOCAL_SIZE_VARS),
        usable,
        node,
    );
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global()
        .map_err(|e| anyhow::anyhow!("cannot size the thread pool to {n} ({why}): {e}"))?;
    Ok((n, why))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_rule_order() {
        // RAYON_NUM_THREADS wins; a bad value is ignored.
        assert_eq!(threads_per_rank(Some("3"), Some(2), 8, 8).0, 3);
        assert_eq!(threads_per_rank(Some("x"), Some(2), 8, 8).0, 4);
        assert_eq!(threads_per_rank(Some("0"), Some(2), 8, 8).0, 4);
        // A rank bound to 2 of 8 cores keeps 2, whatever the local size.
        assert_eq!(threads_per_rank(None, Some(8), 2, 8).0, 2);
        // Unbound: the node split between its ranks, at least one thread.
        assert_eq!(threads_per_rank(None, Some(3), 8, 8).0, 2);
        assert_eq!(threads_per_rank(None, Some(16), 8, 8).0, 1);
        assert_eq!(threads_per_rank(None, None, 8, 8).0, 8);
    }

    #[test]
    fn cpu_lists() {
        assert_eq!(parse_cpu_list("0-3,8,10-11"), Some(7));
        assert_eq!(parse_cpu_list("0"), Some(1));
        assert_eq!(parse_cpu_list("3-1"), None);
        assert_eq!(parse_cpu_list(""), None);
    }
}
