/**
 * The studio's entry point: styles, then the application in `#app`.
 */
import './styles/studio.css';
import { describeError } from './api/errors';
import { Studio } from './app/studio';

const root = document.getElementById('app');
if (root) {
  Studio.start(root).catch((e: unknown) => {
    root.textContent = `The studio failed to start: ${describeError(e)}`;
  });
}
