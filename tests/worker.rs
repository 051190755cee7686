//! A watched call stopped by its front end's signal (apart from the library's unit tests:
//! the stop request it makes is process-wide).

use stillpoint::pipeline::worker::{watched, Stopped};

#[test]
fn a_signal_asks_the_run_to_stop_and_is_returned_once_it_has() {
    let mut looks = 0;
    let outcome = watched(
        || {
            // A run that checks for a stop request between its steps.
            while !stillpoint::solve::cancelled() {
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
            Ok("stopped by request")
        },
        || {
            looks += 1;
            Err("KeyboardInterrupt")
        },
    );
    match outcome {
        Err(Stopped::Signal(e)) => assert_eq!(e, "KeyboardInterrupt"),
        other => panic!("{other:?}"),
    }
    assert_eq!(
        looks, 1,
        "the signal is taken once, then the worker is waited for"
    );
    // The next call clears the request its predecessor left set.
    let cleared = watched(|| Ok(!stillpoint::solve::cancelled()), || Ok::<(), ()>(()));
    assert!(cleared.unwrap());
}
