//! A way to abandon a long computation from outside it without I/O in the solvers: a caller
//! installs a hook for the current thread ([`within`]), and the simulator calls [`check`]
//! once per simulated forcing period (and once per piece of a long record); the hook may
//! unwind (`std::panic::resume_unwind`) to stop the computation, as the explorer's time
//! limit and superseded requests do. Without a hook, `check` does nothing.

use std::cell::RefCell;
use std::sync::Arc;

/// What a hook is: called often, it returns when the computation may go on.
pub type Hook = Arc<dyn Fn() + Send + Sync>;

thread_local! {
    static HOOK: RefCell<Option<Hook>> = const { RefCell::new(None) };
}

/// Restores the hook that was installed before, also when the computation unwinds.
struct Restore(Option<Hook>);

impl Drop for Restore {
    fn drop(&mut self) {
        let previous = self.0.take();
        HOOK.with(|h| *h.borrow_mut() = previous);
    }
}

/// Runs `f` with `hook` called at every [`check`] on this thread (other threads are not
/// affected), then puts back what was installed before.
pub fn within<R>(hook: Hook, f: impl FnOnce() -> R) -> R {
    let previous = HOOK.with(|h| h.borrow_mut().replace(hook));
    let _restore = Restore(previous);
    f()
}

/// Installs `hook` on this thread until it is replaced, and returns the one installed before:
/// for a pool's worker threads, which run the many pieces of one computation ([`within`]
/// scopes a hook to one closure).
pub fn replace(hook: Option<Hook>) -> Option<Hook> {
    HOOK.with(|h| std::mem::replace(&mut *h.borrow_mut(), hook))
}

/// This thread's hook, if one is installed (for the threads a computation starts: they take
/// it over with [`replace`]).
pub fn current() -> Option<Hook> {
    HOOK.with(|h| h.borrow().clone())
}

/// Calls this thread's hook, if one is installed.
pub fn check() {
    // Cloned out of the cell first: the hook may unwind, and must not do so while the cell is
    // borrowed.
    if let Some(hook) = current() {
        hook();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn a_replaced_hook_stays_until_it_is_replaced_again() {
        let calls = Arc::new(AtomicUsize::new(0));
        let c = Arc::clone(&calls);
        assert!(replace(Some(Arc::new(move || _ = c.fetch_add(1, Ordering::SeqCst)))).is_none());
        check();
        within(Arc::new(|| {}), check);
        check();
        assert!(current().is_some());
        assert!(replace(None).is_some());
        assert!(current().is_none());
        check();
        assert_eq!(calls.load(Ordering::SeqCst), 2, "called twice, not inside `within`, not after");
    }

    #[test]
    fn a_hook_runs_inside_and_is_gone_after_even_when_it_unwinds() {
        let calls = Arc::new(AtomicUsize::new(0));
        let c = Arc::clone(&calls);
        within(Arc::new(move || _ = c.fetch_add(1, Ordering::SeqCst)), || {
            check();
            check();
        });
        check();
        assert_eq!(calls.load(Ordering::SeqCst), 2);
        struct Stop;
        let stopped = catch_unwind(AssertUnwindSafe(|| {
            within(Arc::new(|| resume_unwind(Box::new(Stop))), || {
                check();
                unreachable!("the hook unwinds");
            })
        }));
        assert!(stopped.is_err_and(|p| p.is::<Stop>()));
        // The unwinding hook was taken down: this returns.
        check();
    }
}
